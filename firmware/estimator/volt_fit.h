/**
 * @file volt_fit.h
 * @brief The winding's resistance and back-EMF constant from the voltage equation alone: an
 *        instrumental-variable fit over windows of driven periods.
 *
 * Over one sampling period of length T the armature's voltage equation, averaged, reads
 *
 *     u - L (i1 - i0) / T = R (i0 + i1) / 2 + n Ke v
 *
 * with u the voltage applied over the period [V], i0, i1 the measured currents at its start and
 * end [A], v = (phi1 - phi0) / T the period's mean plate velocity from the measured angle [rad/s],
 * L the model's inductance [H] (its +-20 % spread moves the fit by less than 0.3 %: the inductive
 * term averages out) and n Ke the back-EMF constant at the plate [V s/rad]. Every period with
 * |u| >= u_min_V adds its terms to the sums of the block under way; after `block` such periods the
 * block is complete, and the sums over the last `blocks` complete blocks give R and n Ke (a sliding
 * window of blocks x block driven periods, a new result every block).
 *
 * Instrumental variables: v has no model error but the tracks' noise, which in a least-squares
 * regressor would shrink n Ke; the estimator's velocity w = (w0 + w1) / 2 has little noise but,
 * on a unit whose friction and springs are not the model's, errors that follow the motion, which
 * least squares on w takes into n Ke and R (healthy all_varied units: R 0.98 - 1.02 of their own,
 * n Ke up to 1.5 on windows of little motion). So v is the regressor and w the instrument: Z'X
 * theta = Z'y with Z = (i, w), X = (i, v), y the left-hand side (healthy units: R 1.00 - 1.01,
 * README "The fit's R by instrumental variables"). The estimator's own resistance state (ekf.h,
 * dR) takes every error of the voltage equation for a resistance error, the back-EMF constant's
 * above all: a unit whose Ke is 5 - 9 % off the model's reads R + dR 7 - 12 % off in fast motion.
 * The fit reads both constants at once, so it tells shorted turns (R and Ke down together) from a
 * current-sensor gain (R down, Ke as it was: the gain divides R, never Ke).
 *
 * A window is taken only when current and estimated velocity are not (nearly) collinear over it
 * (rho^2 <= rho2_max), else R and n Ke cannot be told apart and the last result stays.
 *
 * Standard deviations: sqrt(var [A^-1 Z'Z A^-T]_jj), A = Z'X, with var the variance per degree of
 * freedom of the residual on w (y - R i - n Ke w: the model's errors, which last for many periods,
 * not white noise) times corr_periods, their correlation length in periods (the default is
 * measured, README "The voltage equation's fit"), plus that of the residual on v (its share of the
 * angle's noise, white).
 *
 * The current measurement's offset: a sensor that reads i + b leaves an intercept u0 = -R b in
 *
 *     u - L (i1 - i0) / T = R_c (i0 + i1) / 2 + n Ke_c v + u0
 *
 * with v = (phi1 - phi0) / T the period's mean velocity from the measured angle (the caller's
 * differentiated angle), so the same window's fit with an intercept reads b = -u0 / R_c. Not with
 * the estimated velocity as the regressor: on a unit whose friction and springs are not the
 * model's, the estimate's errors follow the motion, the intercept takes their mean share, and
 * healthy all_varied units read up to 44 mA (class b's 1.6 ohm in closed-loop driving). The
 * differentiated angle has no such errors but its noise, which would shrink n Ke_c and move u0:
 * so v is the regressor and the estimated velocity the instrument (instrumental variables: the
 * normal equations Z'X theta = Z'y with Z = (i, w, 1), X = (i, v, 1)). Measured on the fault
 * matrix's healthy evaluation runs (150, 8 s): |b| at most 25 mA (least squares on w: 44 mA);
 * with +50 mA, 45 - 64 mA wherever the window lies after the onset (README "The current offset
 * from the fit"). Its standard deviation is sigma^2 (A^-1 Z'Z A^-T), A = Z'X, with the variance of
 * its residual (on v) scaled by corr_periods.
 *
 * No heap, no globals; one call per period, a fixed cost of a few multiply-adds (the 2 x 2 solve
 * once per window).
 */
#ifndef VOLT_FIT_H
#define VOLT_FIT_H

#include <stdint.h>

#include "tv_real.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Longest block [driven periods]. */
#define VFIT_BLOCK_MAX 60000u
/** Most blocks in a window. */
#define VFIT_BLOCKS_MAX 8u
/** vfit_step()'s result bits: this period completed a block and its window gave R and n Ke ... */
#define VFIT_TOOK_FIT 1
/** ... the current's offset. */
#define VFIT_TOOK_OFFSET 2
/** Sums a block keeps. */
#define VFIT_SUMS 14u

/** Configuration. */
typedef struct {
    uint16_t block;           /**< driven periods per block, 100..VFIT_BLOCK_MAX (default 250: 0.25 s of drive) */
    uint8_t blocks;           /**< blocks per window, 1..VFIT_BLOCKS_MAX (default 4) */
    tv_real_t u_min_V;        /**< a period is driven when |u| >= this [V], >= 0 (default 0.5) */
    tv_real_t rho2_max;       /**< a window is taken when the squared correlation of current and velocity
                                   is at most this [-], (0, 1) (default 0.98) */
    tv_real_t corr_periods;   /**< the residuals' correlation length [periods], >= 1 (default 36) */
} vfit_config_t;

/** State and the last window's result. */
typedef struct {
    vfit_config_t cfg;
    tv_real_t l_over_t;       /**< L / T of the model [ohm] */
    tv_real_t s[VFIT_SUMS];   /**< sums over the block under way: i i, i w, w w, i y, w y, y y, i, w, y, i v, w v,
                                   v v, v y, v (w the estimated velocity, v the differentiated angle's) */
    uint16_t n;               /**< driven periods in the block under way */
    tv_real_t ring[VFIT_BLOCKS_MAX][VFIT_SUMS]; /**< the last complete blocks' sums */
    uint8_t next;             /**< the ring's slot the next complete block goes to */
    uint8_t full;             /**< complete blocks in the ring, up to blocks */
    uint8_t valid;            /**< 1 once a window was taken */
    uint32_t windows;         /**< windows taken */
    tv_real_t r_ohm;          /**< R of the last window taken [ohm] */
    tv_real_t r_sigma_ohm;    /**< its standard deviation [ohm] */
    tv_real_t nke_V_s;        /**< n Ke of the last window taken, at the plate [V s/rad] */
    tv_real_t nke_sigma_V_s;  /**< its standard deviation [V s/rad] */
    uint8_t off_valid;        /**< 1 once a window gave the offset below (the centred instruments not collinear) */
    tv_real_t i_off_A;        /**< the current measurement's offset b the same window reads from the instrumental-
                                   variable fit with an intercept (file comment), b = -u0 / R_c [A] */
    tv_real_t i_off_sigma_A;  /**< its standard deviation [A] */
    tv_real_t i_off_vif;      /**< its variance inflation 1 + n q' C_zz q [-] (file comment): how much the
                                   regressors' means confound the intercept; 1 when they are centred, large
                                   when current and velocity barely vary about their means (a slow ramp) */
} vfit_t;

/** Defaults: block 250, blocks 4, u_min_V 0.5, rho2_max 0.98, corr_periods 36. */
void vfit_config_default(vfit_config_t *cfg);

/**
 * Validate and start (nothing taken yet).
 * @param L_H  the model's inductance [H], > 0
 * @param Ts_s the sampling period [s], > 0
 * @return TV_OK, TV_ERR_NULL, TV_ERR_NONFINITE, TV_ERR_CONFIG.
 */
int vfit_init(vfit_t *f, const vfit_config_t *cfg, tv_real_t L_H, tv_real_t Ts_s);

/**
 * One period: u applied over it, the measured currents at its start and end, the estimated
 * velocity at its start and end, the period's mean velocity from the measured angle (its
 * difference over the period, divided by T). Periods with |u| < u_min_V, or with a value not
 * finite, are left out. @return VFIT_TOOK_FIT when this period completed a block and its window gave R and
 * n Ke, VFIT_TOOK_OFFSET when it gave the offset, both or-ed, else 0.
 */
int vfit_step(vfit_t *f, tv_real_t u_V, tv_real_t i0_A, tv_real_t i1_A, tv_real_t w0_rad_s, tv_real_t w1_rad_s,
              tv_real_t v_rad_s);

#ifdef __cplusplus
}
#endif

#endif /* VOLT_FIT_H */
