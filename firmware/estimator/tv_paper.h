/**
 * @file tv_paper.h
 * @brief The paper's Table 1 (Horvath, EMA parameters), the one place these numbers are typed.
 *        SI units, plate side of the gearbox. Used by the estimator's defaults
 *        (tvm_params_default), the host plant's defaults and the paper-as-printed comparison
 *        filter. Plain double constants: converting them to float gives the correctly rounded
 *        float of each decimal value (checked for every entry).
 */
#ifndef TV_PAPER_H
#define TV_PAPER_H

#define TV_PAPER_R_OHM 4.3           /**< armature resistance [ohm] */
#define TV_PAPER_L_H 0.002           /**< armature inductance [H] */
#define TV_PAPER_KE_V_S_RAD 0.017    /**< back-EMF constant [V s/rad] */
#define TV_PAPER_KT_NM_A 0.017       /**< torque constant [N m/A] */
#define TV_PAPER_J_KG_M2 0.0016      /**< inertia at the plate shaft [kg m^2] */
#define TV_PAPER_N_GEAR 40.0         /**< gear ratio [-] */
#define TV_PAPER_MC_NM 0.2           /**< Coulomb friction [N m] */
#define TV_PAPER_M0_NM 0.25          /**< spring preload [N m] */
#define TV_PAPER_C_NM_RAD 0.059      /**< spring stiffness [N m/rad] */
#define TV_PAPER_KV_NM_S_RAD 0.01    /**< viscous friction [N m s/rad] */
#define TV_PAPER_MS_NM 0.3           /**< stiction [N m] */
#define TV_PAPER_WS_RAD_S 1.0        /**< Stribeck velocity [rad/s] */
#define TV_PAPER_TS_S 1e-3           /**< sample time [s] */

#endif /* TV_PAPER_H */
