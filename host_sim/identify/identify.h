/**
 * @file identify.h
 * @brief Parameter identification of the throttle model (firmware/estimator/tv_model.h) from
 *        the calibrated samples of one open-loop bench log (host tool; heap, GSL numerics).
 *
 * METHOD (equation error on the model's own equations; README "Identification"):
 *   0. Signals: u = duty x measured supply (bridge enabled), i and phi calibrated from the log's
 *      counts exactly as the application does. phi is smoothed and differentiated by a
 *      Savitzky-Golay filter (cubic, 2 ID_SG_HALF + 1 samples; coefficients from a GSL least-
 *      squares fit of the window's polynomial), the current smoothed by the same filter.
 *   1. Armature, exact over one period with the input held (the model's own ZOH solution):
 *        i(k+1) = a i(k) + b u(k) - b nKe wbar(k),  a = exp(-R Ts / L), b = (1 - a) / R,
 *      wbar the smoothed velocity over the period: linear least squares in (a, b, b nKe), then
 *      R = (1 - a) / b, L = -R Ts / ln a, nKe; standard deviations by the delta method from the
 *      fit's covariance. (dw/dt-free, and L stays identifiable although L / R < Ts.)
 *   2. Plate, in free motion (away from both stops and limp-home, moving one way over the whole
 *      filter window):
 *        nKt i = J dw/dt + M0 sp(phi) + c phi + Mc sgn(w) + (Ms - Mc) exp(-|w| / ws) sgn(w) + Kv w,
 *      with nKt = nKe (an ideal motor's constants are one number in SI units: tied, not fitted
 *      twice), linear in (J, M0, c, Mc, Ms - Mc, Kv) for a given Stribeck velocity ws; ws by
 *      Brent's method (GSL) on the residual sum of squares over ln ws (variable projection),
 *      its standard deviation from the curvature of that sum. What the log cannot separate is
 *      not fitted: J is held at the default without ID_MIN_SAMPLES / 4 samples at |dw/dt| >=
 *      ID_J_ACC_MIN, Kv without as many at |w| >= ID_KV_W_MIN (the others fitted to the torque
 *      less the held terms); where ws runs to a bound of its search the plate is refitted
 *      without the Stribeck column (Ms, ws not identified; Ms = Mc identified instead where the
 *      drop is insignificant and ID_NODROP_W_RAD_S slow samples show it); a non-physical J, M0,
 *      c, Mc or Kv leaves the whole plate unidentified, and Mc and Kv are identified together
 *      (plate_consistency()).
 *   3. Stops: 50 ms blocks where the plate rests at the travel's ends (the 0.5 % quantiles of
 *      the angle) under a steady push; the contact force (motor torque less the fitted springs)
 *      against the rest angle gives the Hunt-Crossley law a = a0 + dir (F / k)^(1/e) per stop,
 *      the exponent common to both (sl_contact_fit() of the stop-learning routine for each
 *      exponent of a grid, on the blocks pooled into force levels). Blocks settled by a dither
 *      (APP_MODE_IDENT's stop levels) carry no friction and are used alone where a log has them;
 *      otherwise each block is corrected by the friction its last motion left (loading or
 *      unloading, its level searched with the exponent). The onsets a0 are the stop angles,
 *      their standard deviation from a GSL fit at the chosen exponent. A stop is identified
 *      only where a block held a push above the static friction + ID_CONTACT_PROOF_NM (friction
 *      holds a plate anywhere against less) and its onset lies on its side of limp-home.
 *   4. Contact law by the impacts: rest angles pin the law at the small penetrations where a
 *      plate dwells, and several exponents fit them about equally well, each with its own k and
 *      onsets; they differ at an impact's depth, which is what the estimator meets at speed.
 *      Every impact of the log (the measured angle crosses an onset at > 1 rad/s after free
 *      travel; ID_IMP_LEN samples from ID_IMP_PRE before the crossing) is replayed by the
 *      model's plate equation from the smoothed state, each period starting from the MEASURED
 *      current (the armature's model errors do not accumulate) and following the logged voltage
 *      through the identified armature, in 10 us sub-steps near or in a stop and 0.1 ms in free
 *      travel (impact_sse()), for each exponent whose
 *      static fit did not end at a stiffness bound (the law, k and onsets of that fit) and each
 *      damping ratio lambda / k of ID_DAMP_GRID; the pair with the smallest squared angle error
 *      over all impacts is kept; then exponent, k (as a secant at SL_P_REF_RAD, within stop
 *      learning's bounds), damping ratio and both onsets are refined jointly from it by GSL's
 *      Nelder-Mead simplex on the impacts' mean squared angle error plus the rest levels' (the
 *      grid ties each exponent to its static k and onsets; the truth often lies between), kept
 *      when it lowers that cost and does not end held at the upper stiffness bound:
 *      exponent, k, onsets and the damping ratio (identified). Steps 3 and 4 search the
 *      stiffness up to ID_K_WIDEN times stop learning's bound, and the law written is capped at
 *      that bound (a stop stiffer than the model keeps stable keeps its exponent, onsets and
 *      damping ratio). When every law of the grid is at a bound, step 3's law stays and only its
 *      damping ratio is chosen. Needs two impacts at each stop and
 *      steps 1-3 identified; otherwise step 3's law stays and the damping ratio is the
 *      stop-learning rule's 0.16 s/rad (not identified).
 *   Each linear fit is done twice: samples with a residual beyond ID_OUTLIER_SIGMA robust
 *   standard deviations (stop impacts, stick-slip inside the window) are dropped for the second.
 *   Standard deviations: s^2 (X^T X)^-1, s^2 the residual variance, a white-residual figure
 *   that is optimistic for the correlated residuals of smoothed signals; each coefficient's is
 *   widened to the delete-a-block jackknife's (ID_JACK_BLOCKS contiguous blocks) where that is
 *   larger (ls_jackknife()). Neither sees a bias the whole log shares (a log that excites the
 *   model where it is wrong): the excitation rules above are for that. Fit quality: R^2 and the
 *   RMS residual per equation.
 *
 * A parameter is IDENTIFIED when its fit had enough samples and its standard deviation is below
 * ID_REL_SIGMA_MAX of its value (and the value is physical: > 0, Ms >= Mc); otherwise
 * id_result_t::why says what was missing and the caller keeps its default.
 */
#ifndef IDENTIFY_H
#define IDENTIFY_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Half width of the Savitzky-Golay window [samples] (the window is 2 ID_SG_HALF + 1 = 21 ms). */
#define ID_SG_HALF 10
/** A parameter is identified when sigma / |value| is below this [-]. */
#define ID_REL_SIGMA_MAX 0.2
/** Residuals beyond this many robust standard deviations are dropped before the final fit. */
#define ID_OUTLIER_SIGMA 4.0
/** J is identified only with ID_MIN_SAMPLES / 4 samples of free motion at least this fast in
 * acceleration [rad/s^2] (0.07 - 0.1 N m of inertial torque at the classes' J); otherwise it is
 * held at the default and the other plate parameters are fitted with it. */
#define ID_J_ACC_MIN 50.0
/** Kv is identified only with ID_MIN_SAMPLES / 4 samples of free motion at least this fast
 * [rad/s]; otherwise it is held at the default like J. */
#define ID_KV_W_MIN 5.0
/** "No Stribeck drop" (Ms = Mc) is a finding only with ID_MIN_SAMPLES / 4 samples of free
 * motion slower than this [rad/s]: a drop shows below it for every ws of the classes' spread
 * (0.5 - 2 rad/s); at the grid's top ws every sample counts as slower than 2 ws. */
#define ID_NODROP_W_RAD_S 2.0
/** A stop is identified only where a rest held a push into it this much above the static
 * friction (which holds a plate anywhere in its travel) [N m]. */
#define ID_CONTACT_PROOF_NM 0.05
/** Contiguous blocks of the delete-a-block jackknife that widens a fit's sigmas (ls_jackknife()). */
#define ID_JACK_BLOCKS 10
/** Fewest samples a fit needs. */
#define ID_MIN_SAMPLES 200u
/** Room for a reason [bytes]. */
#define ID_WHY_MAX 128u

/** The identified quantities. */
typedef enum {
    ID_P_R = 0,        /**< armature resistance [ohm] */
    ID_P_L,            /**< armature inductance [H] */
    ID_P_NKE,          /**< n Ke = n Kt, plate side [V s/rad] = [N m/A] */
    ID_P_J,            /**< inertia at the plate [kg m^2] */
    ID_P_M0,           /**< spring preload [N m] */
    ID_P_C,            /**< spring rate [N m/rad] */
    ID_P_MC,           /**< Coulomb friction [N m] */
    ID_P_MS,           /**< static friction [N m] */
    ID_P_WS,           /**< Stribeck velocity [rad/s] */
    ID_P_KV,           /**< viscous friction [N m s/rad] */
    ID_P_PHI_CLOSED,   /**< closed stop (contact onset) [rad] */
    ID_P_PHI_OPEN,     /**< open stop (contact onset) [rad] */
    ID_P_K_STOP,       /**< contact stiffness [N m/rad^e] */
    ID_P_STOP_EXP,     /**< Hunt-Crossley exponent e [-] */
    ID_P_STOP_DAMP,    /**< contact damping ratio lambda / k [s/rad] (the model's d_stop = ratio x k) */
    ID_P_COUNT
} id_param_t;

/** The samples of a log, one per period (Ts = 1 ms). Arrays of n, owned by the caller. */
typedef struct {
    size_t n;            /**< number of samples */
    const double *u_V;   /**< voltage applied over [t_k, t_k + Ts) [V] */
    const double *i_A;   /**< measured current at t_k [A] */
    const double *phi_rad; /**< measured angle at t_k [rad] */
    const uint8_t *ok;   /**< 1: sample usable (bridge enabled, plausible angle and current, and
                              exactly one period after the previous sample); 0: not */
    double Ts_s;         /**< sample period [s], > 0 */
} id_data_t;

/** What the identification found. */
typedef struct {
    double value[ID_P_COUNT];      /**< estimates (valid where identified) */
    double sigma[ID_P_COUNT];      /**< their standard deviations (NaN: none) */
    double r_log_temp_C;           /**< the winding's temperature during the log, when given
                                        (id_refer_resistance()): value[ID_P_R] is then referred to
                                        20 degC; NaN: not given, R is the log's as it is [degC] */
    int identified[ID_P_COUNT];    /**< 1: identified (see the file comment) */
    char why[ID_P_COUNT][ID_WHY_MAX]; /**< why not, when not identified */
    size_t n_elec, n_mech;         /**< samples in the final armature and plate fits */
    size_t n_blocks[2];            /**< rest blocks at the closed / open stop */
    double r2_elec, rms_elec_A;    /**< armature fit: R^2 of i(k+1) and RMS residual [A] */
    double r2_mech, rms_mech_Nm;   /**< plate fit: R^2 of the motor torque and RMS residual [N m] */
    double rms_stop_rad;           /**< contact-law fit: RMS residual of the rest angles [rad] */
    size_t n_impacts;              /**< impacts the contact law was chosen by (step 4) */
    double rms_impact_rad;         /**< their RMS angle error with the chosen law [rad] (NaN: none) */
    double travel_lo_rad, travel_hi_rad; /**< smallest and largest smoothed angle of the log [rad] */
    int moved;                     /**< 1: the plate moved (enough free-motion samples for the plate fit) */
    int ms_is_mc;                  /**< 1: no Stribeck drop seen: Ms identified as Mc, the plate refitted without it */
} id_result_t;

/** Name of a parameter as printed ("R", "L", "nKe", ...). */
const char *id_param_name(id_param_t p);
/** Unit of a parameter ("ohm", ...). */
const char *id_param_unit(id_param_t p);

/**
 * Identify the parameters.
 * @param d the samples
 * @param progress NULL, or a stream for one line per stage
 * @param res the result (always written)
 * @return 0; TV_ERR_NULL; TV_ERR_RANGE (fewer samples than one filter window, Ts not > 0);
 *         TV_ERR_IO (out of memory).
 */
int id_run(const id_data_t *d, FILE *progress, id_result_t *res);

/**
 * Refer the identified winding resistance (and its sigma) to 20 degC, the model's reference
 * (firmware/app/app.h, APP_R_REF_TEMP_C), from the winding's temperature during the log:
 * R / (1 + APP_COPPER_ALPHA_PER_K (temp_C - 20)). Once per result.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_RANGE (temp_C outside APP_WINDING_TEMP_MIN_C ..
 *         APP_WINDING_TEMP_MAX_C, or already referred); nothing changes on error.
 */
int id_refer_resistance(id_result_t *res, double temp_C);

#ifdef __cplusplus
}
#endif

#endif /* IDENTIFY_H */
