/**
 * @file sim.h
 * @brief The host simulation core as a library (the host_sim executable and the tests share
 *        it): scenarios that run the firmware's own 1 kHz application, UNCHANGED, against the
 *        high-fidelity plant through the simulation HAL, with comparison estimators run on the
 *        same inputs, and accuracy / consistency metrics.
 *
 * ONE TICK (1 ms), k = 0, 1, ...:
 *   1. the scenario updates the application's control (mode, target) for time t_k = k ms;
 *   2. app_tick(): the application reads the ADC at plant time t_k, estimates, writes duty and
 *      bridge enable to the HAL (sim_hal.c, which commands the plant's H-bridge);
 *   3. the comparison estimators get exactly what the application's filter got: a predict with
 *      the voltage the application applied over the previous period (app_t::u_applied_V; one
 *      predict per elapsed period), then a correct with the same calibrated measurements
 *      app_output_t::z, whenever the application corrected:
 *        (a) "paper set-up, our map": a second ekf_t with ekf_config_paper() (3 measurements
 *            incl. the differentiated angle, paper Q and R, P0 = 100 I, x0 = 0) on the stable
 *            map of tv_model.h;
 *        (b) "paper as printed": paper_filter.h with eq. 21 literally; (b') the same with the
 *            eq. 12 map for the prediction, "paper, eq.12 predict"; (b'') eq. 12 with its exact
 *            Jacobian, "paper, eq.12 + exact Jac." (the paper with errata 3 and 4 corrected);
 *        (c) "measured": the measurements themselves, the velocity being the angle
 *            differentiated over one period (app_output_t::z velocity channel);
 *   4. errors against the plant truth at t_k, NEES, NIS; a row to the CSV / row callback;
 *   5. sim_hal_advance(1 ms): the plant integrates the bridge command over [t_k, t_k + 1 ms).
 *
 * METRICS. RMSEs are over the ticks with t_k >= SIM_TRANSIENT_S (filters start from x0 = 0).
 * NEES = e^T P^-1 e with e = x_app - x_true and the application filter's P after correction
 * (3 degrees of freedom); NIS = y^T S^-1 y from ekf_innov_t (n_used degrees of freedom).
 * Their averages over N ticks are compared with the two-sided 95 % band of an average of N
 * independent chi-square variables: [chi2_q(0.025, D), chi2_q(0.975, D)] / N, D = sum of the
 * dof (3 N for NEES). The chi-square quantile is the Wilson-Hilferty approximation (see
 * sim_chi2_quantile()). Ticks are time-correlated, so the single-run band is a guide; the
 * Monte Carlo band per tick (sim_monte_carlo()) is the proper test.
 *
 * The HAL is a single static plant (sim_hal.h), so runs are sequential: not reentrant.
 */
#ifndef SIM_H
#define SIM_H

#include <stdint.h>
#include <stdio.h>

#include "app.h"
#include "sim_tracking.h"
#include "ekf.h"
#include "plant.h"
#include "plant_fault.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Metrics ignore the ticks before this time [s] (filter convergence from x0 = 0). */
#define SIM_TRANSIENT_S 0.2
/** Longest warm-up (sim_options_t::warmup_s) [s] and its excitation. */
#define SIM_WARMUP_MAX_S 60.0
#define SIM_WARMUP_AMPLITUDE_V 6.0
#define SIM_WARMUP_FREQ_HZ 1.0
/** Tick period of the simulation [s] (APP_PERIOD_US). */
#define SIM_TICK_S 1e-3
/** Window of sim_result_t::nees_window_max [ticks] (100 ms). */
#define SIM_NEES_WINDOW 100u
/** Longest run sim_run() accepts [s]. */
#define SIM_DURATION_MAX_S 600.0
#define SIM_WINDING_TEMP_MIN_C (-40.0) /**< sim_options_t::winding_temp_C range [degC] */
#define SIM_WINDING_TEMP_MAX_C 180.0
/** Distance from a plant stop within which stop_contact_speed_max samples the velocity [rad]. */
#define SIM_CONTACT_NEAR_RAD 0.002
/** Largest number of seeds sim_monte_carlo() accepts. */
#define SIM_MC_SEEDS_MAX 100000u
/** Lower tail probability of the two-sided 95 % chi-square band. */
#define SIM_BAND_P_LO 0.025
/** Upper tail probability of the two-sided 95 % chi-square band. */
#define SIM_BAND_P_HI 0.975

/** Scenarios. */
typedef enum {
    /** the paper's experiment: APP_MODE_SINE 12 V / 5 Hz, 2 s, plant defaults (current noise
     *  0.01 A, angle noise 1e-4 rad, 12-bit ADC) */
    SIM_SCN_PAPER_SINE = 0,
    /** APP_MODE_POSITION, target 0.2, 0.8, 0.05, 1.2 rad, each for 0.5 s (cycling), 2.5 s */
    SIM_SCN_CLOSED_STEPS,
    /** APP_MODE_POSITION, target 0.1 rad for 0.25 s, ramp to 1.2 rad over 1 s, back over 1 s,
     *  hold; 2.5 s */
    SIM_SCN_CLOSED_RAMP,
    /** APP_MODE_CHIRP 12 V, 1 -> 20 Hz over 2 s; 2 s */
    SIM_SCN_CHIRP,
    /** plate at rest at 0.5 rad (inside the stiction band: spring 0.28 N m < Ms 0.3 N m),
     *  APP_MODE_OFF (bridge off): it stays stuck; at 0.5 s a 4.5 V pulse of 40 ms (APP_MODE_STEPS
     *  at 0 Hz) breaks it away, it slides about 0.05 rad opening and sticks again (the spring is
     *  still below stiction); from 1.2 s the voltage ramps up at 5 V/s and the plate breaks away
     *  again near 1.95 s (0.85 A) and opens; 2.2 s */
    SIM_SCN_STUCK_RELEASE,
    /** APP_MODE_SINE 5 V / 0.5 Hz, 4 s: slow motion with stick-slip at each reversal */
    SIM_SCN_SLOW_SINE,
    /** APP_MODE_STEPS +-10 V at 1 Hz, 4 s: the plate dwells 0.5 s against each stop */
    SIM_SCN_OPEN_STEPS,
    /** APP_MODE_SINE 1.5 V / 2 Hz, 2 s: a small excitation that does not break the plate away
     *  from limp-home (standstill) */
    SIM_SCN_STANDSTILL,
    /** closed loop to 0.8 rad, bridge disabled (the springs return the plate to limp-home),
     *  closed loop to the lowest target, bridge disabled again; 0.6 s each, 2.4 s */
    SIM_SCN_LIMP_HOME,
    /** APP_MODE_STOP_LEARN (stop_learn.h): the start-up routine learns both stops, then the
     *  bridge is off; 12 s. sim_result_t::stop_learn_* report it against the plant's stops. */
    SIM_SCN_STOP_LEARN,
    /** APP_MODE_IDENT at 12 V: the identification excitation (app.h), one 30 s sequence; the log
     *  that `identify` reads (host_sim/identify/) */
    SIM_SCN_IDENT,
    /** closed-loop normal driving (the fault matrix's driving cycle): APP_MODE_POSITION through
     *  ten pedal positions between 0.05 and 1.2 rad, one per second, each reached by a ramp at
     *  SIM_DRIVE_RATE_RAD_S and then held; 10 s (repeating when longer). Not in the population's
     *  default mix (its figures stay comparable); the fault matrix runs it. */
    SIM_SCN_DRIVE,
    SIM_SCN_COUNT /**< number of scenarios (not a scenario) */
} sim_scenario_t;

/** Estimators compared (rows of the metrics table). */
typedef enum {
    SIM_EST_APP = 0,        /**< the application's own filter */
    SIM_EST_PAPER_SETUP,    /**< ekf_config_paper() on the stable map (3 meas, paper Q, R, P0, x0) */
    SIM_EST_PAPER_PRINTED,  /**< paper_filter.h, eq. 21 literally (the paper as printed) */
    SIM_EST_PAPER_EQ12,     /**< paper_filter.h predicting with eq. 12 instead (Jacobian still eq. 27) */
    SIM_EST_PAPER_EQ12_EXACT, /**< paper_filter.h with eq. 12 and its exact Jacobian (errata 3, 4
                                   corrected; forward Euler and atan(1e3 x) kept) */
    SIM_EST_MEASURED,       /**< measurements: current, differentiated angle, angle */
    SIM_EST_COUNT           /**< number of estimators (not an estimator) */
} sim_est_t;

/** One logged tick. Angles [rad], velocities [rad/s], currents [A], voltages [V]. */
typedef struct {
    double t_s;                 /**< sample time [s] */
    uint64_t t_us;              /**< sample time the application read with the ADC [us] (hal_adc_read) */
    double truth[TVM_NX];       /**< plant state at t_s */
    uint16_t adc[4];            /**< raw counts the application read (hal.h order) */
    uint8_t driver_fault;       /**< driver-fault input the application read */
    float duty_f;               /**< duty written, exactly as the PWM received it (float) */
    double u_applied_V;         /**< voltage the application applies over [t_s, t_s + 1 ms) as its model sees it */
    double u_bridge_V;          /**< mean true winding voltage over [t_s, t_s + 1 ms) (plant) */
    double supply_V;            /**< the plant's bridge supply in force at t_s, faults included (truth) [V] */
    double duty;                /**< duty written [-] */
    int bridge_enable;          /**< enable written */
    double target_rad;          /**< closed-loop target (NaN in open-loop modes) */
    double z[EKF_NCH];          /**< calibrated measurements (current, differentiated velocity, angle) */
    double x[TVM_NX];           /**< application filter's estimate */
    double r_est_ohm;           /**< its winding resistance R + dR (app_output_t::r_est_ohm) [ohm] */
    double sigma[TVM_NX];       /**< its standard deviations */
    double innov[EKF_NCH];      /**< its innovations (0 on unused channels) */
    double innov_sigma[EKF_NCH];/**< sqrt of the innovation variances (0 on unused channels) */
    double nis;                 /**< NIS of this correction (NaN when no correction) */
    int nis_dof;                /**< its dof (0 when no correction) */
    double nees;                /**< NEES of the application filter (NaN if P not PD) */
    int mode;                   /**< app_mode_t in force */
    uint32_t faults;            /**< latched APP_FAULT_* mask */
    uint32_t dtc_confirmed;     /**< app_output_t::dtc_confirmed (bit per diag_dtc_t) */
    int ekf_status;             /**< status of the application filter's step */
    uint32_t missing_samples;   /**< samples missing before this one */
    double x_paper[TVM_NX];     /**< SIM_EST_PAPER_SETUP estimate */
    double sigma_paper[TVM_NX]; /**< its standard deviations */
    double x_printed[TVM_NX];   /**< SIM_EST_PAPER_PRINTED estimate */
    double x_eq12[TVM_NX];      /**< SIM_EST_PAPER_EQ12 estimate */
    double x_eq12x[TVM_NX];     /**< SIM_EST_PAPER_EQ12_EXACT estimate */
} sim_row_t;

/** Called once per tick with the logged row. */
typedef void (*sim_row_fn)(const sim_row_t *row, void *user);

/** What to run. Initialise with sim_options_default() and change what you need. */
typedef struct {
    sim_scenario_t scenario;   /**< default SIM_SCN_PAPER_SINE */
    double duration_s;         /**< run length [s], 0 = the scenario's default; (0, SIM_DURATION_MAX_S] */
    uint64_t seed;             /**< plant noise seed, default 1 */
    ekf_setup_t setup;         /**< the application filter's measurement set-up, default EKF_SETUP_CURRENT_ANGLE */
    int q_override;            /**< 1: the application filter's Q = ekf_q_from_spectral(qu, qT) */
    double qu_V2_s;            /**< voltage noise density [V^2 s], >= 0 (used when q_override) */
    double qT_Nm2_s;           /**< torque noise density [N^2 m^2 s], >= 0 (used when q_override) */
    double r_current_A2;       /**< > 0: R of the current channel [A^2] (a VARIANCE); 0 keeps the default */
    double r_angle_rad2;       /**< > 0: R of the angle channel [rad^2]; 0 keeps the default */
    double r_velocity_rad2_s2; /**< > 0: R of the differentiated-velocity channel [(rad/s)^2]; 0 keeps */
    int pwm_ripple;            /**< 1: the plant resolves the PWM switching (plant_config_t::pwm_ripple) */
    const plant_config_t *plant; /**< NULL: plant_config_default(); pwm_ripple applies on top */
    const app_config_t *app;   /**< NULL: app_config_default(); the scenario sets the control
                                    mode and its parameters, then setup / Q / R overrides apply */
    /** 0: none; > 0 (at most SIM_WARMUP_MAX_S): the run begins with this long a warm-up of
     *  normal excitation (APP_MODE_SINE SIM_WARMUP_AMPLITUDE_V at SIM_WARMUP_FREQ_HZ: both ways,
     *  reversals at low speed, the open stop touched), and only then the scenario starts, its
     *  time and its scoring counted from there: the filter's adapted parameters (resistance,
     *  friction) have seen the unit before it is scored. Not with stuck_release and stop_learn,
     *  which start from a given plate state. [s] */
    double warmup_s;
    /** The plant winding's temperature [degC], SIM_WINDING_TEMP_MIN_C .. SIM_WINDING_TEMP_MAX_C,
     *  default 20: the plant's R is its configuration's (the resistance at 20 degC) times
     *  1 + APP_COPPER_ALPHA_PER_K (T - 20). Constant over the run. */
    double winding_temp_C;
    /** 1: the application is told the winding's temperature temp_reading_C (app_set_winding_temp(),
     *  as the CAN command's WindingTemp would) before its first step; 0 (default): unknown. */
    int temp_reading;
    double temp_reading_C;     /**< [degC], within app_set_winding_temp()'s range (used with temp_reading) */
    const plant_fault_list_t *faults; /**< NULL, or faults injected into the plant and its sensors
                                    (plant_fault.h): each tick t_k the faults in force at t_k are set
                                    before the application reads the ADC */
    uint32_t drop_tick_every;  /**< 0: never; N > 1: every N-th tick the application is not run
                                    (a missing sample, predicted across by the application) */
    FILE *csv;                 /**< NULL, or a stream for the CSV log (header + one line per tick) */
    FILE *events;              /**< NULL, or a stream for the diagnostic events: header
                                    "t_us,status,fault_class,dtc", one line per event (diag_csv.h) */
    sim_row_fn row_fn;         /**< NULL, or called once per tick */
    void *row_user;            /**< passed to row_fn */
} sim_options_t;

/** Results of one run. RMSEs are NaN where an estimator has no such state. */
typedef struct {
    sim_scenario_t scenario;    /**< scenario run */
    uint64_t seed;              /**< plant noise seed */
    double duration_s;          /**< simulated time [s] */
    uint32_t n_ticks;           /**< application ticks run */
    uint32_t n_scored;          /**< ticks scored (t >= SIM_TRANSIENT_S) */
    double rmse[SIM_EST_COUNT][TVM_NX]; /**< RMSE of (current [A], velocity [rad/s], angle [rad]) */
    double meas_bias[TVM_NX];   /**< mean error of the measurements (sensor + calibration bias) */
    double nees_avg;            /**< average NEES over the scored ticks with P positive definite */
    double nees_lo, nees_hi;    /**< 95 % band of that average: chi2_q(p, 3 N) / N */
    uint32_t nees_n;            /**< N of that average */
    double nis_avg;             /**< average NIS over the scored ticks with a correction */
    double nis_lo, nis_hi;      /**< 95 % band: chi2_q(p, D) / N, D = total dof */
    double nis_dof_avg;         /**< D / N (2 or 3 for a fixed set-up) */
    uint32_t nis_n;             /**< N of that average */
    double nis_ch_avg[EKF_NCH]; /**< average NIS of each channel over its corrections (1 dof; NaN: unused) */
    uint32_t faults;            /**< latched APP_FAULT_* mask at the end */
    uint32_t dtc_confirmed;     /**< diagnostic codes confirmed at the end (bit per diag_dtc_t) */
    uint32_t fault_ticks;       /**< ticks with any fault latched */
    double first_fault_t_s;     /**< time of the first fault [s], NaN if none */
    uint32_t ekf_rejections;    /**< ticks whose application-filter step failed */
    uint32_t missing_samples;   /**< sum of app_output_t::missing_samples */
    uint32_t hal_errors;        /**< app_tick() returns != TV_OK */
    uint32_t paper_setup_rejections; /**< failed steps of SIM_EST_PAPER_SETUP */
    uint32_t paper_printed_resets;   /**< divergence-guard resets of SIM_EST_PAPER_PRINTED */
    uint32_t paper_eq12_resets;      /**< divergence-guard resets of SIM_EST_PAPER_EQ12 */
    uint32_t paper_eq12x_resets;     /**< divergence-guard resets of SIM_EST_PAPER_EQ12_EXACT */
    sim_tracking_t tracking;         /**< closed-loop tracking figures of the plant's angle (sim_tracking.h) */
    double nees_window_max;          /**< largest average NEES over SIM_NEES_WINDOW consecutive scored ticks (NaN: too short) */
    uint32_t consistency_episodes;   /**< times the application's consistency monitor raised a flag (nis_monitor.h) */
    uint32_t consistency_flag_ticks; /**< ticks with a consistency flag raised */
    double r_est_ohm;                /**< the filter's winding resistance R + dR at the end [ohm] */
    double r_sigma_ohm;              /**< its standard deviation [ohm] (0: no resistance-error state) */
    double r_true_ohm;               /**< the plant's winding resistance [ohm] (at its temperature) */
    double r_20_ohm;                 /**< the estimate referred to 20 degC (app_output_t::r_20_ohm) [ohm];
                                          NaN when the application was not told the temperature */
    double r_true_20_ohm;            /**< the plant's at 20 degC [ohm] */
    double r_fit_ohm;                /**< the voltage equation's fit of R, its last window at the end (volt_fit.h) [ohm];
                                          NaN when no window was taken */
    double r_fit_sigma_ohm;          /**< its standard deviation [ohm] (NaN likewise) */
    double nke_fit_V_s;              /**< the fit's back-EMF constant at the plate, n Ke [V s/rad] (NaN likewise) */
    double nke_fit_sigma_V_s;        /**< its standard deviation [V s/rad] (NaN likewise) */
    double nke_true_V_s;             /**< the plant's n Ke [V s/rad] (with an injected fault's) */
    double i_off_fit_A;              /**< the current measurement's offset the fit with an intercept reads (vfit_t::i_off_A)
                                          [A]; NaN when no window gave one */
    double i_off_fit_sigma_A;        /**< its standard deviation [A] (NaN likewise) */
    uint32_t fit_windows;            /**< windows the fit took */
    /* (the two here fill the padding after fit_windows) */
    uint16_t fit_base_windows;       /**< the last step's app_output_t::fit_base_windows: windows summed toward
                                          learning the baseline below */
    uint8_t fit_base_state;          /**< the last step's app_output_t::fit_base_state (APP_FIT_BASE_*) */
    double fit_base_r_ohm;           /**< the fit's per-unit baseline at the end (given or learned: app_t::fit_base_r_ohm),
                                          R at 20 degC [ohm]; NaN when none */
    double fit_base_nke_V_s;         /**< its n Ke [V s/rad]; NaN when none */
    double friction_rel;             /**< the filter's friction level relative to its model's, 1 + f, at the end [-] */
    double friction_rel_sigma;       /**< its standard deviation [-] (0: no friction-error state) */
    double friction_rel_true;        /**< the plant's Coulomb friction relative to the filter model's [-] */
    double friction_check_max;       /**< the largest 1 + f the friction check judged: at a step whose sigma(f) was
                                          inside diag.friction_sigma_max (its slow reading's gate) [-]; NaN: none */
    double friction_fast_max;        /**< the largest friction of the torque signature the check judged
                                          (diag_detect_t::friction_fast, its fast reading) [-]; NaN: none */
    double preload_rel;              /**< the filter's spring preload relative to its model's, 1 + m, at the end [-] */
    double preload_rel_sigma;        /**< its standard deviation [-] (0: no preload-error state) */
    double preload_rel_true;         /**< the plant's preload relative to the filter model's [-] */
    double stop_onset_rad[2];        /**< the estimator's stop onsets at the end (closed, open; tracked online, stop_track.h) [rad] */
    uint32_t stop_track_accepted;    /**< rest blocks that moved an onset */
    uint32_t stop_track_refused;     /**< rest blocks refused (outside the tracking window) */
    uint32_t impact_learned;         /**< impacts the contact law was learned from (impact_learn.h) */
    uint32_t impact_k_updates;       /**< of which updated the stiffness */
    uint32_t impact_abandoned;       /**< impacts armed but not learned from */
    double contact_k;                /**< the estimator's contact stiffness at the end [N m/rad^e] */
    double contact_alpha_s_rad;      /**< its damping ratio d / k at the end [s/rad] */
    double contact_exponent;         /**< its exponent (0: Kelvin-Voigt) */
    double contact_w_coupling;       /**< the contact inflation's velocity coupling at the end (ekf_config_t::contact_w_coupling) [-] */
    double impact_rebound_err_last;            /**< the last learned impact's rebound error relative to its speed (il_t::rebound_err_last) [-] (NaN: none) */
    int stop_learn_phase;            /**< sl_phase_t at the end (SL_IDLE: the routine did not run) */
    int stop_learn_error;            /**< sl_error_t at the end */
    double stop_learn_closed_rad;    /**< learned closed stop [rad] (NaN unless SL_DONE) */
    double stop_learn_open_rad;      /**< learned open stop [rad] (NaN unless SL_DONE) */
    double stop_learn_onset_closed_rad; /**< fitted contact onset, closed stop [rad] (NaN unless SL_DONE) */
    double stop_learn_onset_open_rad;   /**< fitted contact onset, open stop [rad] (NaN unless SL_DONE) */
    double stop_learn_k;             /**< fitted contact stiffness [N m/rad^e] (NaN unless SL_DONE) */
    double stop_learn_exponent;      /**< fitted contact exponent (common to both stops; NaN unless SL_DONE) */
    double stop_learn_s;             /**< time the routine ran [s] */
    double dtc_confirm_t_s[DIAG_DTC_COUNT]; /**< time of each code's first confirmation [s] (NaN: never) */
    double dtc_pending_t_s[DIAG_DTC_COUNT]; /**< time of each code's first pending event [s] (NaN: never) */
    uint32_t dtc_events;             /**< diagnostic events drained from the application */
    uint32_t dtc_events_lost;        /**< events the application's queue dropped (diag_t::events_lost) */
    double stop_contact_speed_max;   /**< largest plant velocity INTO a stop [rad/s] at a tick whose plant
                                          angle was within SIM_CONTACT_NEAR_RAD of that stop or beyond it,
                                          while APP_MODE_STOP_LEARN was in force (NaN: never there) */
} sim_result_t;

/** Monte Carlo results (sim_monte_carlo()). */
typedef struct {
    sim_scenario_t scenario;    /**< scenario run */
    uint32_t n_seeds;           /**< M runs, seeds seed, seed + 1, ..., seed + M - 1 */
    uint64_t first_seed;        /**< seed of the first run */
    double duration_s;          /**< simulated time per run [s] */
    double rmse_mean[SIM_EST_COUNT][TVM_NX]; /**< mean over seeds of each RMSE */
    double rmse_max[SIM_EST_COUNT][TVM_NX];  /**< largest over seeds */
    double anees;               /**< mean NEES over all seeds and scored ticks */
    double band_lo, band_hi;    /**< 95 % band of an M-run average NEES: chi2_q(p, 3M) / M */
    double anees_lo, anees_hi;  /**< 95 % band of the grand average if all samples were independent */
    double frac_ticks_in_band;  /**< fraction of scored ticks whose M-seed average NEES is in [band_lo, band_hi] */
    uint32_t n_ticks_scored;    /**< scored ticks per run */
    double anis;                /**< mean NIS over all seeds and scored corrections */
    double nis_dof_avg;         /**< its mean dof */
    uint32_t runs_with_faults;  /**< runs that latched any fault */
    uint32_t ekf_rejections;    /**< summed over runs */
    uint32_t missing_samples;   /**< summed over runs */
    uint32_t paper_printed_resets; /**< summed over runs */
} sim_mc_result_t;

/** Progress report of sim_monte_carlo(): run done (1..n) of n. */
typedef void (*sim_progress_fn)(uint32_t done, uint32_t n, void *user);

/** Defaults: paper_sine, its default duration, seed 1, current + angle set-up, no overrides, no log. */
void sim_options_default(sim_options_t *opt);

/** Scenario name ("paper_sine", "closed_steps", "closed_ramp", "chirp", "stuck_release"); "?" if invalid. */
const char *sim_scenario_name(sim_scenario_t s);

/** One line saying what scenario s does (for --help and the README). */
const char *sim_scenario_description(sim_scenario_t s);

/**
 * Scenario by name.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_RANGE for an unknown name (*out unchanged).
 */
int sim_scenario_from_name(const char *name, sim_scenario_t *out);

/** Default duration of a scenario [s] (0 if invalid). */
double sim_scenario_duration_s(sim_scenario_t s);

/** 1 if a run of scenario s may begin with a warm-up (sim_options_t::warmup_s); 0 for
 *  stuck_release and stop_learn, which start from a given plate state, and for an invalid s. */
int sim_scenario_takes_warmup(sim_scenario_t s);

/** Estimator row label ("app filter", "paper set-up, our map", ...); "?" if invalid. */
const char *sim_est_name(sim_est_t e);

/** Short identifier of an estimator for JSON / CSV ("app", "paper_setup", ...); "?" if invalid. */
const char *sim_est_id(sim_est_t e);

/**
 * Run one scenario for one seed.
 * @param opt options (sim_options_default() + changes)
 * @param res results (always written: zeroed / NaN first)
 * @return TV_OK; TV_ERR_NULL; TV_ERR_RANGE (duration, scenario, drop_tick_every == 1);
 *         TV_ERR_NONFINITE / TV_ERR_CONFIG (a Q / R override or a plant / application
 *         configuration rejected by its init, or a fault that the plant refuses at its full
 *         size, e.g. a supply sag larger than the supply); TV_ERR_IO (CSV write failed); TV_ERR_NUMERIC
 *         (the plant integration failed).
 */
int sim_run(const sim_options_t *opt, sim_result_t *res);

/**
 * Monte Carlo: run opt's scenario for n_seeds seeds opt->seed .. opt->seed + n_seeds - 1 and
 * aggregate (see sim_mc_result_t). opt->csv and opt->row_fn are not used. Allocates the
 * per-tick NEES accumulator on the heap (host only).
 * @param progress NULL, or called after each run
 * @return TV_OK; TV_ERR_NULL; TV_ERR_RANGE (n_seeds 0 or > SIM_MC_SEEDS_MAX); TV_ERR_IO (out of
 *         memory); or the first failing sim_run()'s status.
 */
int sim_monte_carlo(const sim_options_t *opt, uint32_t n_seeds, sim_progress_fn progress, void *user,
                    sim_mc_result_t *out);

/**
 * Standard normal quantile (inverse CDF), Acklam's rational approximation refined by one
 * Halley step (relative error < 1e-12 for p in (1e-300, 1 - 1e-16)). NaN outside (0, 1).
 */
double sim_normal_quantile(double p);

/**
 * Chi-square quantile by the Wilson-Hilferty approximation:
 *   chi2_q(p, d) ~ d (1 - 2 / (9 d) + z_p sqrt(2 / (9 d)))^3,  z_p = sim_normal_quantile(p),
 * clamped at 0. Error: for d = 3 about -0.03 at p = 0.025 (0.18 vs 0.216) and -0.02 at 0.975
 * (9.33 vs 9.35); relative error below 1e-3 for d >= 30 and 1e-4 for d >= 300, which is the
 * regime of the averaged NEES / NIS bands. NaN when p is outside (0, 1) or d <= 0.
 */
double sim_chi2_quantile(double p, double dof);

/** Write the CSV header line (column names with units). @return TV_OK; TV_ERR_NULL; TV_ERR_IO. */
int sim_csv_header(FILE *f);

/** Write one CSV line (%.9g). @return TV_OK; TV_ERR_NULL; TV_ERR_IO. */
int sim_csv_row(FILE *f, const sim_row_t *row);

/** Readable metrics table of one run. @return TV_OK; TV_ERR_NULL; TV_ERR_IO. */
int sim_result_print(FILE *f, const sim_result_t *res);

/** Metrics of one run as a JSON object (NaN as null). @return TV_OK; TV_ERR_NULL; TV_ERR_IO. */
int sim_result_json(FILE *f, const sim_result_t *res);

/** Readable Monte Carlo table. @return TV_OK; TV_ERR_NULL; TV_ERR_IO. */
int sim_mc_print(FILE *f, const sim_mc_result_t *mc);

/** Monte Carlo results as a JSON object (NaN as null). @return TV_OK; TV_ERR_NULL; TV_ERR_IO. */
int sim_mc_json(FILE *f, const sim_mc_result_t *mc);

#ifdef __cplusplus
}
#endif

#endif /* SIM_H */
