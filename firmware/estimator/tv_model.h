/**
 * @file tv_model.h
 * @brief Throttle-valve model: parameters, continuous dynamics, and the discrete prediction map
 *        used by the EKF together with its analytic Jacobian.
 *
 * States (plate side of the gearbox, SI units):
 *   x[0] = i    armature current                        [A]
 *   x[1] = w    plate angular velocity                  [rad/s]
 *   x[2] = phi  plate angle, 0 at limp-home, + opening  [rad]
 * Input: u = armature voltage (H-bridge duty x supply)  [V]
 *
 * Continuous model (firmware/estimator/MODEL.md, paper eqs. 1-3 with the gear ratio in the torque):
 *   L di/dt   = u - R i - Ke n w
 *   J dw/dt   = n Kt i - M0 sp(phi) - c phi - Mf(w) + Mstop(phi, w)
 *   dphi/dt   = w
 *   Mf(w)     = g(w) sgn(w) + Kv w
 *   g(w)      = Mc + (Ms - Mc) exp(-|w|_e / ws),  |w|_e = sqrt(w^2 + e_w^2) - e_w
 *   sp(phi)   = phi / sqrt(phi^2 + e_phi^2)        (limp-home preload sign, smoothed over e_phi)
 *   Mstop     = torque of the hard stops on the plate, positive = opening, no adhesion;
 *               Kelvin-Voigt when stop_exponent = 0 (the default):
 *       p_lo = phi_closed - phi > 0:  Mstop = +max(0, k_stop p_lo - d_stop w)
 *       p_hi = phi - phi_open   > 0:  Mstop = -max(0, k_stop p_hi + d_stop w)
 *       otherwise 0;
 *               Hunt-Crossley when stop_exponent = e >= 1 (a learned or identified contact law,
 *               README "Stop contact"; k_stop in N m/rad^e, d_stop = lambda in N m s/rad^(e+1)):
 *       p_lo > 0:  Mstop = +max(0, p_lo^e (k_stop - d_stop w))
 *       p_hi > 0:  Mstop = -max(0, p_hi^e (k_stop + d_stop w))
 *
 * DISCRETE PREDICTION MAP x(k+1) = f(x(k), u(k)) over Ts, and why it is built this way.
 *   The paper's forward Euler step is unstable at Ts = 1 ms (1 - R Ts / L = -1.15) and its
 *   atan(1e3 x) sign is far too stiff for explicit stepping (MODEL.md errata 1-2). This map:
 *   - splits Ts into N equal sub-steps h = Ts / N (N = params.substeps, 1..TVM_SUBSTEPS_MAX),
 *     so the stiff hard-stop contact (sqrt(k_stop/J) = 2500 rad/s, h*2500 = 0.25 at N = 10)
 *     and the fast mechanics are resolved;
 *   - solves the armature equation exactly over each sub-step (zero-order hold of u and of the
 *     back-EMF), which is stable for every h: the current never flips sign from numerics;
 *   - treats Coulomb/Stribeck friction implicitly as a set-valued law: the friction impulse over
 *     a sub-step can stop the plate but never reverse it, and a plate whose driving torque is
 *     below stiction stays exactly at rest (no chatter, no creep). In closed form this is a
 *     soft threshold; viscous friction is implicit too;
 *   - integrates the angle with the new velocity (semi-implicit, symplectic Euler), which does
 *     not pump energy into the spring/stop oscillators.
 *   Each sub-step, with constants a = exp(-R h / L), b = (1 - a) / R, kappa = 1/(1 + h Kv / J):
 *       i1   = a i + b (u - Ke n w)
 *       T    = n Kt i1 - M0 sp(phi) - c phi + Mstop(phi, w)
 *       z    = w + (h / J) T
 *       D    = (h / J) g(w)
 *       w1   = kappa * sgn(z) * max(|z| - D, 0)
 *       phi1 = phi + h w1
 *   The map is piecewise smooth: its derivative jumps only on the sets |z| = D (stick/slip
 *   boundary), k_stop p + d_stop w = 0 and p = 0 (contact onset). Elsewhere, including w = 0,
 *   phi = 0 and inside the stops, it is differentiable, and tvm_step() returns that derivative
 *   exactly (chain rule through the N sub-steps: F = J_N ... J_1). While the plate sticks,
 *   the velocity row of a sub-step Jacobian is zero: that is the true derivative of the map.
 *
 * Hard-stop angles, contact law, smoothing widths and N are not in the paper; their defaults
 * are documented at tvm_params_default().
 */
#ifndef TV_MODEL_H
#define TV_MODEL_H

#include "tv_real.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Number of states (i, w, phi). */
#define TVM_NX 3
/** Upper bound on the number of internal sub-steps of the prediction map. */
#define TVM_SUBSTEPS_MAX 50

/** State indices. */
enum { TVM_I = 0, TVM_W = 1, TVM_PHI = 2 };

/** Physical parameters of the actuator and of the discrete map. All SI, plate side. */
typedef struct {
    /* paper Table 1 */
    tv_real_t R_ohm;          /**< armature resistance [ohm], > 0 */
    tv_real_t L_H;            /**< armature inductance [H], > 0 */
    tv_real_t Ke_V_s_rad;     /**< back-EMF constant, motor side [V s/rad], >= 0 */
    tv_real_t Kt_Nm_A;        /**< torque constant, motor side [N m/A], >= 0 */
    tv_real_t J_kg_m2;        /**< inertia at the plate shaft [kg m^2], > 0 */
    tv_real_t n_gear;         /**< gear ratio motor:plate [-], > 0 */
    tv_real_t Mc_Nm;          /**< Coulomb friction torque [N m], >= 0 */
    tv_real_t M0_Nm;          /**< spring preload torque at limp-home [N m], >= 0 */
    tv_real_t c_Nm_rad;       /**< spring stiffness [N m/rad], >= 0 */
    tv_real_t Kv_Nm_s_rad;    /**< viscous friction [N m s/rad], >= 0 */
    tv_real_t Ms_Nm;          /**< stiction (breakaway) torque [N m], >= Mc_Nm */
    tv_real_t ws_rad_s;       /**< Stribeck velocity [rad/s], > 0 */
    /* not in the paper */
    tv_real_t phi_closed_rad; /**< closed hard stop [rad], < 0 (below limp-home) */
    tv_real_t phi_open_rad;   /**< open hard stop [rad], > 0 */
    tv_real_t k_stop_Nm_rad;  /**< contact stiffness of both stops [N m/rad], >= 0 */
    tv_real_t d_stop_Nm_s_rad;/**< contact damping of both stops [N m s/rad], >= 0 */
    tv_real_t stop_exponent;  /**< contact law: 0 = Kelvin-Voigt, else the Hunt-Crossley exponent in [1, 3] */
    tv_real_t e_phi_rad;      /**< smoothing width of the preload sign at limp-home [rad], > 0 */
    tv_real_t e_w_rad_s;      /**< smoothing width of |w| inside the Stribeck exponential [rad/s], > 0 */
    tv_real_t Ts_s;           /**< sample period of the map [s], > 0 (1e-3 for 1 kHz) */
    int substeps;             /**< internal sub-steps N per Ts, 1..TVM_SUBSTEPS_MAX */
} tvm_params_t;

/** The model with constants derived from the parameters; filled by tvm_init(), read-only after. */
typedef struct {
    tvm_params_t p;     /**< the parameters it was built from */
    tv_real_t h_s;      /**< sub-step length Ts / N [s] */
    tv_real_t a;        /**< exp(-R h / L): armature decay over a sub-step [-] */
    tv_real_t b_A_V;    /**< (1 - a) / R: armature gain over a sub-step [A/V] */
    tv_real_t h_J;      /**< h / J [s/(kg m^2)] */
    tv_real_t kappa;    /**< 1 / (1 + h Kv / J): implicit viscous factor [-] */
    tv_real_t nKt_Nm_A; /**< n Kt [N m/A] */
    tv_real_t nKe_V_s;  /**< n Ke [V s/rad] */
} tvm_t;

/**
 * Default parameters: the paper's Table 1, plus
 *   phi_closed = -0.10 rad (-5.7 deg, OEM bodies close 5-7 deg below limp-home),
 *   phi_open   = phi_closed + 84 deg = 1.3660766 rad,
 *   k_stop = 1e4 N m/rad (8 mrad penetration for a 20 rad/s impact), d_stop = 2.4 N m s/rad
 *   (damping ratio 0.3 against J), stop_exponent = 0 (Kelvin-Voigt), e_phi = 1e-4 rad (the limp-home detent is a
 *   mechanical contact: a plate resting in it feels the whole preload within 0.1 mrad, so a wider
 *   smoothing lets the model slide where the real plate rests; README "Limp-home detent"),
 *   e_w = 1e-3 rad/s, Ts = 1e-3 s, N = 10.
 */
void tvm_params_default(tvm_params_t *p);

/**
 * Validate parameters and derive the map's constants.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_NONFINITE if a parameter is NaN/Inf; TV_ERR_CONFIG if one
 *         is outside the range documented at its field. On error *m is not written.
 */
int tvm_init(tvm_t *m, const tvm_params_t *p);

/** g(w) = Mc + (Ms - Mc) exp(-|w|_e / ws): friction magnitude [N m] at velocity w [rad/s]. */
tv_real_t tvm_friction_level(const tvm_t *m, tv_real_t w_rad_s);

/** Hard-stop torque on the plate [N m], positive = opening, at angle phi [rad] and velocity w. */
tv_real_t tvm_stop_torque(const tvm_t *m, tv_real_t phi_rad, tv_real_t w_rad_s);

/**
 * The springs' torque M0 sp(phi) + c phi [N m] at angle phi [rad], positive = toward closing
 * (what the motor must balance to hold the plate), the preload sign smoothed as the map's
 * (sp = phi / sqrt(phi^2 + e_phi^2)). From the parameters alone: the start-up routine, the stop
 * tracker and the impact learning call it with the model they are given. Inline: the stop
 * tracker and the controller's feed-forward call it every period (as a call it cost the
 * Cortex-M4F application step 16 instructions, firmware_report).
 */
static inline tv_real_t tvm_spring_torque(const tvm_params_t *p, tv_real_t phi_rad)
{
    const tv_real_t e = p->e_phi_rad;
    return p->M0_Nm * phi_rad / TV_SQRT(phi_rad * phi_rad + e * e) + p->c_Nm_rad * phi_rad;
}


/**
 * One step of the discrete prediction map over Ts: x_next = f(x, u), and optionally its
 * Jacobian F = df/dx at (x, u). x and x_next may alias. F may be NULL (prediction only).
 * Inputs are assumed finite (the EKF validates them); cost is fixed: N sub-steps, no loops
 * that depend on data.
 */
void tvm_step(const tvm_t *m, const tv_real_t x[TVM_NX], tv_real_t u_V, tv_real_t x_next[TVM_NX],
              tv_real_t F[TVM_NX][TVM_NX]);

/**
 * tvm_step() with an extra torque d_Nm [N m] on the plate (positive = opening), held over Ts:
 * the disturbance-torque state of the EKF (ekf.h, "contact torque"). With d_Nm = 0 it is
 * tvm_step() exactly. G, when F and G are both given, receives dx_next/dd_Nm (the input column of
 * the Jacobian, same chain rule through the sub-steps); G is ignored when F is NULL.
 */
void tvm_step_dist(const tvm_t *m, const tv_real_t x[TVM_NX], tv_real_t d_Nm, tv_real_t u_V,
                   tv_real_t x_next[TVM_NX], tv_real_t F[TVM_NX][TVM_NX], tv_real_t G[TVM_NX]);

/** Augmented (disturbance) inputs of tvm_step_aug(): a torque on the plate, a winding-resistance
 *  error, a relative friction error and a relative spring-preload error. */
enum { TVM_A_TORQUE = 0, TVM_A_DR = 1, TVM_A_FRIC = 2, TVM_A_PRELOAD = 3, TVM_NA = 4 };
/** g_cols of tvm_step_aug(): every column of G. */
#define TVM_G_ALL ((1u << TVM_NA) - 1u)

/**
 * tvm_step() with the augmented inputs a = (d_Nm, dR_ohm, f, m) held over Ts: an extra torque d_Nm on
 * the plate [N m] (positive = opening), an error dR_ohm of the winding resistance [ohm] (the
 * winding is R + dR), a relative error f [-] of the Coulomb friction (the level g(w) + f Mc:
 * Coulomb friction Mc (1 + f), static friction Ms + f Mc, the Stribeck excess Ms - Mc kept;
 * wear, contamination, ice, f > -1) and a relative error m
 * [-] of the spring preload (M0 (1 + m); a fatigued or broken return spring, m > -1). The resistance error enters each sub-step explicitly, as the voltage -dR i at the
 * sub-step's initial current: i1 = a i + b (u - n Ke w - dR i), stable while |b dR| < a (the EKF
 * bounds dR far inside that); the friction error enters D = (h / J) (g(w) + f Mc), the preload error the preload torque. With a = 0 it is tvm_step() exactly. G, when F and G are both
 * given, receives dx_next/da (column TVM_A_TORQUE: d/dd_Nm, TVM_A_DR: d/ddR_ohm, TVM_A_FRIC: d/df,
 * TVM_A_PRELOAD: d/dm), by the same
 * chain rule through the sub-steps as F; G is ignored when F is NULL. g_cols selects the columns
 * computed (bit q: column q; TVM_G_ALL for all); the others are set to 0 (the EKF asks only for
 * the columns of the states it carries: each costs about 10 % of the map).
 */
void tvm_step_aug(const tvm_t *m, const tv_real_t x[TVM_NX], const tv_real_t a_in[TVM_NA], tv_real_t u_V,
                  tv_real_t x_next[TVM_NX], tv_real_t F[TVM_NX][TVM_NX], tv_real_t G[TVM_NX][TVM_NA],
                  unsigned g_cols);

/**
 * tvm_step_aug(), and the largest magnitude of the stop torque M_stop over the period's
 * sub-steps, each evaluated at the sub-step's start as the map uses it [N m] (0 when no sub-step
 * starts inside a stop), in *peak_stop_Nm unless NULL: the impact timing of the EKF
 * (ekf_config_t::impact_timing) scales by it. In *hold_frac unless NULL, how firmly static
 * friction holds the plate at the period's end: 1 - |z| / D of its last sub-step when every
 * sub-step held the plate stuck (|z| <= D: z the velocity the sub-step's net torque would reach,
 * D what the friction level takes away; at rest 1 - |net torque| / static friction: 1 = no net
 * torque, 0 = at breakaway), -1 when any sub-step slipped. The EKF's stuck-plate noise
 * (ekf_config_t::stuck_q_min) scales by it.
 */
void tvm_step_aug_peak(const tvm_t *m, const tv_real_t x[TVM_NX], const tv_real_t a_in[TVM_NA], tv_real_t u_V,
                       tv_real_t x_next[TVM_NX], tv_real_t F[TVM_NX][TVM_NX], tv_real_t G[TVM_NX][TVM_NA],
                       unsigned g_cols, tv_real_t *peak_stop_Nm, tv_real_t *hold_frac);

#ifdef __cplusplus
}
#endif

#endif /* TV_MODEL_H */
