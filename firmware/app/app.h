/**
 * @file app.h
 * @brief The 1 kHz application step, the same on every platform:
 *        raw ADC counts -> physical units (calibration) -> plausibility checks -> EKF ->
 *        control (open-loop excitation or closed-loop position) -> PWM duty and bridge enable;
 *        or, in APP_MODE_EXTERNAL, estimation alone with the duty another controller applied
 *        (replay of logged bench streams: host_sim/replay/replay.h).
 *
 * app_step() is pure (inputs in, outputs out, state in the caller-owned app_t); app_tick() in
 * app_tick.c wraps it with the HAL for the platforms. Nothing here touches hardware.
 *
 * Safe state: when a plausibility check fails for more than its debounce count, or the driver
 * reports a fault, the output goes to PWM 0 with the bridge disabled (the springs return the
 * plate to limp-home) and a fault flag latches until app_clear_faults().
 */
#ifndef APP_H
#define APP_H

#include <stdint.h>

#include "diag.h"
#include "diag_detect.h"
#include "ekf.h"
#include "nis_monitor.h"
#include "volt_fit.h"
#include "stop_learn.h"
#include "stop_track.h"
#include "impact_learn.h"
#include "tv_model.h"
#include "tv_real.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Application period [us]. */
#define APP_PERIOD_US 1000u
/** Track agreement (app_output_t::tps_diff_rad): the difference of the two calibrated tracks is
 *  taken every APP_TPS_AGREE_DECIM-th step (the steps whose app_t::n_steps is a multiple of it:
 *  a trend needs no 1 kHz, and the Cortex-M4F step has 34 instructions to spare) and averaged over
 *  APP_TPS_AGREE_N such samples, 1 s: long against the sensor noise (a count, 0.45 mrad, per
 *  track), short against the wear of a track's wiper that it is there to trend. */
#define APP_TPS_AGREE_DECIM 8u
#define APP_TPS_AGREE_N 125u
/** Upper bound of app_limits_t::max_gap_periods. */
#define APP_MAX_GAP_PERIODS 100u

/** Operating modes. */
typedef enum {
    APP_MODE_OFF = 0,         /**< PWM 0, bridge disabled; estimator runs */
    APP_MODE_SINE = 1,        /**< open loop: u = amplitude sin(2 pi f t) (the paper's experiment) */
    APP_MODE_STEPS = 2,       /**< open loop: square wave of +-amplitude at frequency f */
    APP_MODE_CHIRP = 3,       /**< open loop: sine sweeping f0 -> f1 over chirp_period */
    APP_MODE_POSITION = 4,    /**< closed loop on the estimated angle */
    /**
     * Observer of another controller (replay of bench logs, an ECU listening next to the real
     * controller): the duty and bridge enable that controller applied come in with each sample
     * (app_input_t::duty_ext, bridge_ext) and the estimator predicts the next period with them,
     * exactly as it does with its own command in the other modes (same float duty times the
     * measured supply; the open-bridge voltage when disabled). No control law runs.
     * Outputs: out->duty / bridge_enable echo the external command while no fault is latched
     * and are 0 / 0 otherwise (the safe state, as in every mode); the prediction keeps using
     * the external command, because that is what the actuator receives. An invalid command
     * (duty NaN or Inf, |duty| > 1, enable not 0/1) latches APP_FAULT_EXT_CMD and is treated as
     * a disabled bridge for the prediction; it is never used as a number.
     */
    APP_MODE_EXTERNAL = 5,
    /**
     * Start-up stop learning (stop_learn.h): entering the mode (app_set_control()) starts the
     * routine; it drives the plate slowly into each stop, and when it is done the learned stops
     * replace the model's (estimator and position limits alike) and the mode returns to
     * APP_MODE_OFF. A failed routine learns nothing and also returns to APP_MODE_OFF;
     * app_stop_learn() reports either.
     */
    APP_MODE_STOP_LEARN = 6,
    /**
     * Open-loop identification excitation (README "Identification"): a fixed, deterministic
     * voltage sequence of APP_IDENT_PERIOD_MS (30 s), repeating, with its voltages scaled by
     * amplitude_V / 12 V (the table is written for amplitude_V = 12 V): slow and fast swings over
     * the whole travel both ways (sines at 0.5, 1, 2.5 and 5 Hz), voltage steps with dwells against
     * both stops, each stop held at four decreasing voltages (0.75, 0.5, 0.35, 0.25 x the
     * amplitude), each reached through a decaying 100 Hz dither that shakes the friction off
     * (contact law, stop angles, R at stall; level and dither stay within the amplitude, so a
     * 12 V sequence fits a 12.5 V supply), and a slow sine for low-speed reversals. What `identify` needs from a log
     * (host_sim/identify/). app_ident_voltage() gives the sequence itself.
     */
    APP_MODE_IDENT = 7
} app_mode_t;

/** Length of the APP_MODE_IDENT sequence [ms]; it repeats after this. */
#define APP_IDENT_PERIOD_MS 30000u

/** Fault flags (bit mask, latched). */
enum {
    APP_FAULT_CURRENT_RANGE = 1u << 0,  /**< current ADC outside its plausible counts */
    APP_FAULT_TPS1_RANGE = 1u << 1,     /**< track 1 outside its plausible counts (open/short) */
    APP_FAULT_TPS2_RANGE = 1u << 2,     /**< track 2 outside its plausible counts */
    APP_FAULT_TPS_DISAGREE = 1u << 3,   /**< the two tracks disagree by more than the limit */
    APP_FAULT_SUPPLY_RANGE = 1u << 4,   /**< supply voltage outside its window */
    APP_FAULT_DRIVER = 1u << 5,         /**< H-bridge driver fault input active */
    APP_FAULT_ESTIMATOR = 1u << 6,      /**< the EKF rejected its inputs repeatedly */
    APP_FAULT_TIMING = 1u << 7,         /**< samples missing / time going backwards */
    APP_FAULT_EXT_CMD = 1u << 8         /**< APP_MODE_EXTERNAL: invalid external duty / enable */
};

/** Count-to-unit calibration of the ECU's analogue front end. */
typedef struct {
    uint16_t adc_max_counts;       /**< full scale, 4095 for 12 bits */
    tv_real_t current_offset_counts; /**< counts at 0 A */
    tv_real_t current_A_per_count; /**< [A/count] */
    tv_real_t tps1_counts_at_zero; /**< track 1 counts at phi = 0 (limp-home) */
    tv_real_t tps1_rad_per_count;  /**< [rad/count], > 0 */
    tv_real_t tps2_counts_at_zero; /**< track 2 counts at phi = 0 */
    tv_real_t tps2_rad_per_count;  /**< [rad/count], < 0 (falling track) */
    tv_real_t supply_V_per_count;  /**< [V/count] */
} app_calib_t;

/** Plausibility limits and debounce. */
typedef struct {
    uint16_t current_min_counts, current_max_counts; /**< plausible current counts */
    uint16_t tps_min_counts, tps_max_counts;         /**< plausible counts of both tracks */
    tv_real_t tps_disagree_max_rad;                  /**< |phi1 - phi2| above this fails */
    tv_real_t supply_min_V, supply_max_V;            /**< supply window [V] */
    uint16_t debounce_trip;  /**< consecutive failing samples that trip a fault (>= 1) */
    /**
     * Largest gap predicted across in one step, in periods (1..APP_MAX_GAP_PERIODS). A step
     * predicts once per elapsed period, so this bounds its worst-case time: (1 + missing)
     * predictions. Longer gaps, or time going backwards, latch APP_FAULT_TIMING and predict
     * only this many periods. Default APP_MAX_GAP_PERIODS (replay of bench logs); a real-time
     * target sets what its budget allows (the ECU: 4, about 16,100 instructions).
     */
    uint16_t max_gap_periods;
} app_limits_t;

/** Open-loop excitation and closed-loop control parameters. */
typedef struct {
    app_mode_t mode;
    tv_real_t amplitude_V;     /**< excitation amplitude [V] (sine, steps, chirp) */
    tv_real_t freq_Hz;         /**< sine / step frequency, chirp start [Hz] */
    tv_real_t chirp_f1_Hz;     /**< chirp end frequency [Hz] */
    tv_real_t chirp_period_s;  /**< chirp sweep duration, then it restarts [s] */
    tv_real_t target_rad;      /**< closed-loop target angle [rad] */
    tv_real_t target_margin_rad; /**< targets are kept this far inside the hard stops [rad] */
    tv_real_t kp_V_rad, ki_V_rad_s, kd_V_s_rad; /**< PID gains on angle error [V/rad, V/(rad s), V s/rad] */
    tv_real_t i_limit_V;       /**< anti-windup clamp of the integral term [V] */
    tv_real_t duty_limit;      /**< |duty| <= this, in (0, 1] */
} app_control_t;

/** Everything app_init() needs. */
typedef struct {
    tvm_params_t model;   /**< estimator model parameters */
    ekf_config_t ekf;     /**< estimator configuration (set-up, Q, R, ...) */
    nism_config_t nism;   /**< consistency monitor (nis_monitor.h) */
    vfit_config_t vfit;   /**< the voltage equation's fit of R and n Ke (volt_fit.h) */
    sl_config_t stop_learn; /**< start-up stop learning (APP_MODE_STOP_LEARN, stop_learn.h) */
    st_config_t stop_track; /**< online stop tracking in service (stop_track.h) */
    il_config_t impact_learn; /**< the stops' contact damping and stiffness from impacts in service (impact_learn.h) */
    diag_detect_config_t diag; /**< fault detectors of the diagnostic codes (firmware/diag/diag_detect.h) */
    app_calib_t calib;
    app_limits_t limits;
    app_control_t control;
} app_config_t;

/** Inputs of one step. */
typedef struct {
    uint16_t adc[4];       /**< raw counts: current, tps1, tps2, supply (hal.h order) */
    uint64_t t_us;         /**< sample time [us] */
    uint8_t driver_fault;  /**< H-bridge driver fault input */
    /** APP_MODE_EXTERNAL only (not read in other modes): the PWM duty another controller applies
     *  over the period that starts at this sample, [-1, 1], as the PWM receives it (float). */
    float duty_ext;
    /** APP_MODE_EXTERNAL only (not read in other modes): 1 if that controller's bridge is
     *  enabled over the period, 0 if not. */
    uint8_t bridge_ext;
} app_input_t;

/** Outputs of one step, with everything worth logging. */
typedef struct {
    float duty;            /**< PWM duty to apply, [-1, 1] */
    uint8_t bridge_enable; /**< 1: bridge enabled */
    tv_real_t u_cmd_V;     /**< voltage the controller asked for [V] */
    tv_real_t z[EKF_NCH];  /**< measurements in units: current [A], velocity [rad/s] (differentiated angle), angle [rad] */
    tv_real_t supply_V;    /**< measured supply [V] */
    tv_real_t x[TVM_NX];   /**< estimate after correction (A, rad/s, rad) */
    tv_real_t sigma[TVM_NX]; /**< its standard deviations */
    tv_real_t r_est_ohm;   /**< the filter's winding resistance R + dR (ekf_resistance_error()) [ohm] */
    tv_real_t r_sigma_ohm; /**< its standard deviation [ohm]; 0 when the filter has no resistance-error state */
    tv_real_t r_20_ohm;    /**< condition monitoring: R + dR referred to APP_R_REF_TEMP_C, (R + dR) / (1 +
                                APP_COPPER_ALPHA_PER_K (T - 20 degC)) with T the winding temperature of
                                app_set_winding_temp() [ohm]; 0 while that temperature is unknown */
    tv_real_t friction_rel;       /**< the filter's friction level relative to its model's, 1 + f (ekf_friction_error()) [-] */
    tv_real_t friction_rel_sigma; /**< its standard deviation [-]; 0 when the filter has no friction-error state */
    tv_real_t preload_rel;        /**< the filter's spring preload relative to its model's, 1 + m (ekf_preload_error()) [-] */
    tv_real_t preload_rel_sigma;  /**< its standard deviation [-]; 0 when the filter has no preload-error state */
    tv_real_t stop_closed_rad;    /**< the estimator's closed-stop contact onset in use (learned, then tracked) [rad] */
    tv_real_t stop_open_rad;      /**< its open-stop contact onset in use [rad] */
    tv_real_t tps_diff_rad;       /**< track agreement (condition monitoring): mean of phi1 - phi2 over the
                                       last APP_TPS_AGREE_N samples (every APP_TPS_AGREE_DECIM-th step)
                                       with both tracks plausible (exponentially weighted; a running
                                       mean until that many) [rad]; 0 before the first */
    tv_real_t tps_diff_sd_rad;    /**< the standard deviation of phi1 - phi2 over the same samples [rad] */
    tv_real_t fit_r_ohm;          /**< condition monitoring (TV_HEALTH_4): the winding resistance R of the
                                       voltage equation's fit (app_t::vfit, volt_fit.h), its last window [ohm];
                                       0 until its first window. Within 1 - 2 % where R + dR (r_est_ohm)
                                       can be 7 - 12 % off: it reads the back-EMF constant at once */
    tv_real_t fit_r_sigma_ohm;    /**< its standard deviation [ohm]; 0 until the first window */
    tv_real_t fit_nke_V_s;        /**< the fit's back-EMF constant at the plate, n Ke [V s/rad]; 0 until the
                                       first window */
    tv_real_t fit_i_off_A;        /**< the current measurement's offset the fit reads (vfit_t::i_off_A, P1A04's
                                       reading) [A]; 0 until a window gave one */
    tv_real_t fit_base_r_ohm;     /**< the fit's per-unit baseline in force (given or learned): R at
                                       APP_R_REF_TEMP_C [ohm]; 0 while none (persist it once learned:
                                       diag.fit_base_r_ohm) */
    tv_real_t fit_base_nke_V_s;   /**< its n Ke at the plate [V s/rad]; 0 while none (diag.fit_base_nke_V_s) */
    ekf_innov_t innov;     /**< innovations, their variances, NIS */
    int ekf_status;        /**< status of this step's correction (0 ok) */
    uint32_t faults;       /**< latched APP_FAULT_* mask */
    uint32_t missing_samples; /**< samples missing before this one (predicted across) */
    uint32_t degraded;     /**< APP_DEGRADED_* mask: what this step's correction had to do without */
    uint32_t consistency;  /**< consistency-monitor flags raised now (NISM_FLAG(EKF_CH_*), nis_monitor.h):
                                the model does not explain that channel's data */
    uint32_t dtc_confirmed; /**< diagnostic codes confirmed now: bit (1u << diag_dtc_t) (firmware/diag/diag.h) */
    uint8_t dtc_action;    /**< diag_action_t in force (applied to duty and enable above) */
    /* (the fit's baseline's state here, after dtc_action: the two fill the padding at the struct's
     * end, so the output app_step() clears every step does not grow) */
    uint8_t fit_base_state;    /**< the fit's per-unit baseline (fit_base_r_ohm above; TV_HEALTH_5
                                    FitBaseState): APP_FIT_BASE_NONE (none, and none learned:
                                    diag.fit_base_windows = 0), APP_FIT_BASE_LEARNING (none yet,
                                    diag.fit_base_windows > 0), APP_FIT_BASE_IN_FORCE (given or learned;
                                    an ECU stores it when this turns APP_FIT_BASE_IN_FORCE with a baseline
                                    other than the one it stored: stop_learn.h sl_nvm_t) */
    uint16_t fit_base_windows; /**< the fit's windows summed toward the learning under way (app_t::fit_base_n);
                                    0 when none is */
} app_output_t;

/**
 * Graceful loss of a channel (app_output_t::degraded, per step). A channel that is implausible
 * this sample (outside its plausible counts: at an ADC rail, an open or shorted track) is left
 * out of the correction and the others still correct; a position track whose range fault has
 * latched stays out until the fault is cleared, and the angle comes from the other track alone
 * (the limp mode of an ECU's estimation: one track, flagged). When both tracks are in range but
 * disagree, nothing tells which one is right: the angle is left out. The latched faults keep
 * their action (safe state) on the outputs; the per-code actions (limited authority on one
 * track, ...) belong to the diagnostic codes.
 */
enum {
    APP_DEGRADED_CURRENT = 1u << 0, /**< current channel left out of this correction */
    APP_DEGRADED_TPS1 = 1u << 1,    /**< track 1 lost: the angle is track 2 alone */
    APP_DEGRADED_TPS2 = 1u << 2,    /**< track 2 lost: the angle is track 1 alone */
    APP_DEGRADED_ANGLE = 1u << 3    /**< no usable angle this sample (both tracks lost, or they disagree) */
};

/** Application state. Allocate statically; initialise with app_init(). */
typedef struct {
    app_config_t cfg;
    ekf_t ekf;
    uint64_t t0_us, last_t_us;
    uint32_t n_steps;
    uint8_t started;
    uint32_t faults;
    uint16_t debounce[8];     /**< per check, consecutive failures */
    uint16_t ekf_fail_run;    /**< consecutive EKF rejections */
    tv_real_t u_applied_V;    /**< voltage applied over the last period (input of the next predict) */
    uint8_t open_after_missed; /**< 1: a sample was missed and the outputs forced off then: the
                                    periods after the one that ran with u_applied_V ran open */
    tv_real_t last_angle_rad; /**< last plausible angle measurement (for differentiated velocity) */
    uint64_t last_angle_t_us; /**< its sample time [us] */
    uint8_t have_last_angle;  /**< 1 once a plausible angle was seen */
    tv_real_t integ_V;        /**< PID integral state [V] */
    uint32_t n_estimator_resets; /**< times app_clear_faults() restarted the estimator */
    nism_t nism;              /**< consistency monitor on the estimator's innovations */
    vfit_t vfit;              /**< the voltage equation's fit (volt_fit.h): R and n Ke over driven periods */
    tv_real_t vf_i_prev;      /**< the measured current of the last sample [A] (the fit's period start) */
    tv_real_t vf_w_prev;      /**< the estimated velocity after the last sample's correction [rad/s] */
    sl_t sl;                  /**< stop-learning routine (APP_MODE_STOP_LEARN) and its last result */
    st_t st;                  /**< online stop tracking (stop_track.h): the estimator's stops follow the unit */
    il_t il;                  /**< impact learning (impact_learn.h): the estimator's contact law follows the unit's impacts */
    diag_t diag;              /**< diagnostic codes; the platform drains its events (diag_event_pop()) */
    diag_detect_t ddet;       /**< the detectors' state */
    uint8_t diag_bridge_on;   /**< 1: the bridge drove the period now ending (the open-winding check's condition) */
    uint8_t vf_prev_ok;       /**< 1: the last sample had a plausible current and angle and a correction */
    tv_real_t tps_diff_mean;  /**< track agreement: weighted mean of phi1 - phi2 [rad] (app_output_t::tps_diff_rad) */
    tv_real_t tps_diff_var;   /**< its weighted variance [rad^2] */
    tv_real_t tps_diff_sd;    /**< sqrt(tps_diff_var) [rad] (app_output_t::tps_diff_sd_rad) */
    uint32_t tps_diff_n;      /**< samples in it, saturating at APP_TPS_AGREE_N */
    uint8_t winding_temp_known; /**< 1: winding_temp_C holds the winding's temperature (app_set_winding_temp()) */
    tv_real_t winding_temp_C;   /**< the winding's temperature [degC] while known */
    tv_real_t r_temp_factor;    /**< 1 + APP_COPPER_ALPHA_PER_K (winding_temp_C - APP_R_REF_TEMP_C); 1 while unknown */
    tv_real_t r_temp_inv;       /**< 1 / r_temp_factor */
    /* the fit's per-unit baseline (diag_detect_config_t::fit_base_*): given, or learned here */
    tv_real_t fit_base_r_ohm;   /**< the baseline's R at APP_R_REF_TEMP_C [ohm]; 0: none (yet) */
    tv_real_t fit_base_nke_V_s; /**< its n Ke [V s/rad]; 0: none (yet) */
    tv_real_t fit_base_sum_r;   /**< learning: sum of the windows' R referred to APP_R_REF_TEMP_C [ohm] */
    tv_real_t fit_base_sum_k;   /**< learning: sum of their n Ke [V s/rad] */
    uint16_t fit_base_n;        /**< learning: windows summed */
    uint8_t fit_base_state;     /**< APP_FIT_BASE_* (app_output_t::fit_base_state), set where fit_base_r_ohm is:
                                     app_init() and the learning (one copy per step) */
} app_t;

/**
 * Calibration matching the host_sim plant's default front end (documented in host_sim/plant/plant.h):
 * 12-bit ADC, 3.3 V reference, current sense 1.65 V + 0.1 V/A, tracks 0.1..0.9 x 5 V over the
 * stop-to-stop travel through a 0.66 divider, supply through 1/6.
 */
void app_calib_default(app_calib_t *c, const tvm_params_t *p);

/** Default limits, control (the paper's 12 V / 5 Hz sine), model and EKF configuration. */
void app_config_default(app_config_t *cfg);

/** Validate and initialise. @return TV_OK, TV_ERR_NULL, TV_ERR_NONFINITE, TV_ERR_CONFIG. */
int app_init(app_t *app, const app_config_t *cfg);

/**
 * One 1 ms step. Never fails: bad inputs become faults and the safe state, and are reported in
 * *out. A gap in t_us (missing samples) is predicted across, up to limits.max_gap_periods
 * periods; a larger gap or time going backwards sets APP_FAULT_TIMING.
 */
void app_step(app_t *app, const app_input_t *in, app_output_t *out);

/**
 * Clear latched faults (e.g. on a CAN command); the debounce counters restart. When
 * APP_FAULT_ESTIMATOR was latched the estimator restarts from its configured x0 and P0
 * (app_t::n_estimator_resets counts it): the state it kept refusing would be refused for ever.
 */
void app_clear_faults(app_t *app);

/**
 * Change mode and control parameters at run time; validated like app_init(). Resets the PID
 * integrator (a new mode or new gains start clean); use app_set_target() to move the target.
 */
int app_set_control(app_t *app, const app_control_t *ctl);

/**
 * Move the closed-loop target angle [rad] without resetting the integrator (ramps, step
 * sequences, CAN commands). It is clamped into the stops' margin when used.
 * @return TV_OK, TV_ERR_NULL, TV_ERR_NONFINITE.
 */
int app_set_target(app_t *app, tv_real_t target_rad);

/**
 * The winding's resistance and temperature. The model's R (motor.R in parameter files, what
 * identify writes) is the winding's resistance at APP_R_REF_TEMP_C; copper's rises by
 * APP_COPPER_ALPHA_PER_K per kelvin, +27 % at 90 degC. The estimator follows a warm winding with
 * its resistance error dR either way. With the temperature known, the resistance check compares
 * R + dR with R (1 + alpha (T - 20 degC)), the condition monitoring reports R + dR referred to
 * 20 degC (app_output_t::r_20_ohm, TV_HEALTH_3 ResistanceRef20), and on an identified unit the
 * tighter bound r_high_frac_known of firmware/diag/diag_detect.h applies (a drift of +25 % is a
 * fault, not the engine bay's heat).
 */
#define APP_R_REF_TEMP_C 20.0
#define APP_COPPER_ALPHA_PER_K 0.00393 /**< copper's temperature coefficient of resistance at 20 degC [1/K] */
#define APP_WINDING_TEMP_MIN_C (-40.0) /**< app_set_winding_temp() accepts [min, max] [degC] */
#define APP_WINDING_TEMP_MAX_C 180.0
/** A learned baseline of the fit (diag_detect_config_t::fit_base_windows) is kept when its R at
 *  APP_R_REF_TEMP_C lies within this fraction of the model's (the class's +-20 % spread and a
 *  temperature reading's error) ... */
#define APP_FIT_BASE_R_BAND 0.3
/** ... and its n Ke within this fraction of the model's (the class's +-10 %) [-]. */
#define APP_FIT_BASE_K_BAND 0.15
/** app_output_t::fit_base_state: no baseline, and none learned (diag.fit_base_windows = 0) ... */
#define APP_FIT_BASE_NONE 0u
/** ... none yet, learning (diag.fit_base_windows > 0) ... */
#define APP_FIT_BASE_LEARNING 1u
/** ... a baseline in force, given (diag.fit_base_r_ohm, fit_base_nke_V_s) or learned. */
#define APP_FIT_BASE_IN_FORCE 2u

/**
 * Set the winding's temperature (a sensor, or the engine controller's estimate over CAN:
 * TV_CMD_CONTROL WindingTemp), or declare it unknown (known = 0; temp_C is then ignored). It
 * holds until set again.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_NONFINITE; TV_ERR_RANGE (outside APP_WINDING_TEMP_MIN_C ..
 *         APP_WINDING_TEMP_MAX_C). On error nothing changes.
 */
int app_set_winding_temp(app_t *app, int known, tv_real_t temp_C);

/**
 * The stop-learning routine's state: phase (SL_DONE: phi_closed_rad / phi_open_rad were
 * learned and are in use; SL_FAILED: error says why, the stops are unchanged; SL_IDLE: never
 * run). NULL if app is NULL.
 */
const sl_t *app_stop_learn(const app_t *app);

/**
 * Put stops learned earlier (a parameter file, the ECU's sl_nvm_t record) into use: the
 * estimator's model and the position limits. Validated like the model (closed < 0 < open).
 * @return TV_OK; TV_ERR_NULL; TV_ERR_NONFINITE; TV_ERR_CONFIG. On error nothing changes.
 */
int app_set_stops(app_t *app, tv_real_t phi_closed_rad, tv_real_t phi_open_rad);

/**
 * Tell the application that the platform forced its outputs off this period after a failed PWM
 * write (app_step() ran and chose the outputs): the estimator then predicts the next period
 * with the bridge open.
 */
void app_outputs_forced_off(app_t *app);

/**
 * Tell the application that this period's ADC read failed (app_step() did not run) and the
 * platform forced its outputs off: the period that just ended still ran with the voltage
 * app_step() chose for it, and the estimator predicts it with that voltage; only the periods
 * after it are predicted with the bridge open.
 */
void app_sample_missed(app_t *app);

/**
 * The APP_MODE_IDENT voltage [V] at t_ms milliseconds into the sequence (taken modulo
 * APP_IDENT_PERIOD_MS), for an amplitude of amplitude_V (12 V: the table as written). Pure,
 * bounded (one pass over a table of fixed length).
 */
tv_real_t app_ident_voltage(uint32_t t_ms, tv_real_t amplitude_V);

#ifdef __cplusplus
}
#endif

#endif /* APP_H */
