/**
 * @file paper_filter.h
 * @brief FOR COMPARISON ONLY, never in firmware: the paper's extended Kalman filter transcribed
 *        AS PRINTED (Horvath, "State Space Estimation for an Electromechanical Actuator Valve
 *        using Extended Kalman Filter"), errors included, so that the project can measure what
 *        the published filter actually delivers. firmware/estimator/MODEL.md lists the errata.
 *
 * What is transcribed (double precision, states x = (i [A], w [rad/s], phi [rad])):
 *   - model of eq. 12: forward Euler over Ts with sign(x) ~ (2/pi) atan(1e3 x) (section 3.3);
 *     M_Stop is omitted because the paper never defines it (erratum 5);
 *   - Jacobian Phi exactly as printed in eq. 27, including its errors:
 *       Phi11 = 1 - R Ts / L          (-1.15 at Ts = 1 ms: erratum 1)
 *       Phi12 = +n Ke Ts / L          (sign wrong: erratum 3)
 *       Phi13 = 0
 *       Phi21 = n Kt Ts / J
 *       Phi22 = 1 - Kv Ts / J - 1e3 Ts (Mc + (Ms - Mc)) exp(-|w / ws|) / (J pi (1 + 1e6 w^2))
 *               (Stribeck derivative dropped, 2/pi misplaced: erratum 3)
 *       Phi23 = -c Ts / J - 1e3 Ts M0 Ts / (J pi (1 + 1e6 phi^2))   (spurious extra Ts)
 *       Phi31 = 0, Phi32 = Ts, Phi33 = 1
 *   - prediction, eq. 21 LITERALLY: x^-(k+1) = Phi x(k) + G u(k), G = (Ts / L, 0, 0)^T, i.e. with
 *     the linearisation instead of the nonlinear map (erratum 4; the spring preload and the
 *     friction offsets vanish from the state prediction). PAPER_PREDICT_EQ12 predicts with the
 *     eq. 12 map instead, and PAPER_JACOBIAN_EQ12_EXACT propagates the covariance with the
 *     exact derivative of that map, for comparison with those readings of the paper;
 *   - covariance eq. 22: P^- = Phi P Phi^T + Q;
 *   - correction eqs. 18-20 with H = I (3 measurements: current, the differentiated angle as
 *     "velocity", angle): K = P^- (P^- + R)^-1, x = x^- + K (z - x^-), P = (I - K) P^- (standard
 *     form, not Joseph, not symmetrised, as printed);
 *   - section 3.3: x0 = 0, P0 = 100 I, Q = 0.01 I, R = diag(1e-4, 1, 1e-8).
 *
 * Not in the paper: a divergence guard so that a simulation run completes. After every predict
 * and correct, when any state or covariance entry is non-finite, a state exceeds its bound in
 * x_abs_max, a variance exceeds var_max, or (P^- + R) is singular, the filter is reset to x0, P0
 * and n_resets is incremented. The number of resets is part of the result.
 */
#ifndef PAPER_FILTER_H
#define PAPER_FILTER_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Number of states and of measurements of the paper's filter. */
#define PAPER_NX 3

/** Which state prediction to use. */
typedef enum {
    PAPER_PREDICT_EQ21 = 0, /**< x^- = Phi x + G u with the eq. 27 Jacobian (the paper as printed) */
    PAPER_PREDICT_EQ12 = 1  /**< x^- = f_eq12(x, u) (forward Euler of the nonlinear model) */
} paper_predict_t;

/** Which Jacobian propagates the covariance. */
typedef enum {
    PAPER_JACOBIAN_EQ27 = 0,      /**< eq. 27 as printed (the paper as printed) */
    PAPER_JACOBIAN_EQ12_EXACT = 1 /**< the exact derivative of the eq. 12 map (a corrected reading) */
} paper_jacobian_t;

/** Configuration. Units are those of the states; defaults from paper_filter_config_default(). */
typedef struct {
    double R_ohm, L_H, Ke_V_s_rad, Kt_Nm_A, J_kg_m2, n_gear; /**< paper Table 1 */
    double Mc_Nm, M0_Nm, c_Nm_rad, Kv_Nm_s_rad, Ms_Nm, ws_rad_s; /**< paper Table 1 */
    double Ts_s;             /**< sampling period [s], 1e-3; > 0 */
    double sign_gain;        /**< a in sign(x) ~ (2/pi) atan(a x), 1e3 (paper section 3.3); > 0 */
    paper_predict_t predict; /**< state prediction, PAPER_PREDICT_EQ21 */
    paper_jacobian_t jacobian; /**< covariance Jacobian, PAPER_JACOBIAN_EQ27 */
    double x0[PAPER_NX];     /**< initial state, 0 */
    double P0[PAPER_NX][PAPER_NX]; /**< initial covariance (variances), 100 I */
    double Q[PAPER_NX][PAPER_NX];  /**< process noise covariance per Ts, 0.01 I */
    double r[PAPER_NX];      /**< measurement noise VARIANCES: 1e-4 A^2, 1 (rad/s)^2, 1e-8 rad^2 */
    double x_abs_max[PAPER_NX]; /**< divergence guard: |x_j| above this resets; 1e3 A, 1e4 rad/s, 1e3 rad */
    double var_max;          /**< divergence guard: a variance above this resets; 1e12 */
} paper_filter_config_t;

/** Filter state. */
typedef struct {
    paper_filter_config_t cfg; /**< configuration in force */
    double x[PAPER_NX];        /**< state estimate (A, rad/s, rad) */
    double P[PAPER_NX][PAPER_NX]; /**< covariance (variances); not symmetrised, as printed */
    uint32_t n_predict;        /**< predictions done */
    uint32_t n_correct;        /**< corrections done */
    uint32_t n_resets;         /**< divergence-guard resets to x0, P0 */
} paper_filter_t;

/** The paper's configuration (Table 1, section 3.3), PAPER_PREDICT_EQ21, guard bounds as documented. */
void paper_filter_config_default(paper_filter_config_t *cfg);

/**
 * Validate and set x = x0, P = P0.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_NONFINITE; TV_ERR_CONFIG (a parameter out of its range, a
 *         non-positive variance in r, a non-positive guard bound). On error *pf is not written.
 */
int paper_filter_init(paper_filter_t *pf, const paper_filter_config_t *cfg);

/**
 * Eq. 12 (forward Euler, atan sign, no M_Stop): x_next = f(x, u). x and x_next may alias.
 * Does nothing when a pointer is NULL.
 */
void paper_filter_f_eq12(const paper_filter_config_t *cfg, const double x[PAPER_NX], double u_V,
                         double x_next[PAPER_NX]);

/** Eq. 27 as printed: Phi at x. Does nothing when a pointer is NULL. */
void paper_filter_phi_eq27(const paper_filter_config_t *cfg, const double x[PAPER_NX],
                           double Phi[PAPER_NX][PAPER_NX]);

/**
 * The exact Jacobian of paper_filter_f_eq12() at x (what eq. 27 should have been: Phi12
 * negative, the Stribeck derivative kept, 2/pi in place, no extra Ts). Does nothing when a
 * pointer is NULL.
 */
void paper_filter_phi_eq12_exact(const paper_filter_config_t *cfg, const double x[PAPER_NX],
                                 double Phi[PAPER_NX][PAPER_NX]);

/**
 * Time update with u held over Ts (eqs. 21/22, or eq. 12 for PAPER_PREDICT_EQ12), then the guard.
 * @return TV_OK (also when the guard reset the filter: see n_resets); TV_ERR_NULL;
 *         TV_ERR_NONFINITE (u NaN/Inf: nothing changed).
 */
int paper_filter_predict(paper_filter_t *pf, double u_V);

/**
 * Measurement update with z = (current [A], differentiated velocity [rad/s], angle [rad])
 * (eqs. 18-20), then the guard.
 * @param innov optional (may be NULL): the residual z - x^- of eq. 30.
 * @return TV_OK (also after a guard reset); TV_ERR_NULL; TV_ERR_NONFINITE (a measurement
 *         NaN/Inf: nothing changed).
 */
int paper_filter_correct(paper_filter_t *pf, const double z[PAPER_NX], double innov[PAPER_NX]);

#ifdef __cplusplus
}
#endif

#endif /* PAPER_FILTER_H */
