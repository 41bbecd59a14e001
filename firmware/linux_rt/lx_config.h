/**
 * @file lx_config.h
 * @brief Configuration file of the Linux controller (throttle_linux): every device name and
 *        path, real-time settings, CAN settings, the start-up control and the calibration.
 *
 * FORMAT. One "key = value" per line; '#' starts a comment (a value cannot contain '#');
 * blank lines are ignored; whitespace around key and value is dropped; a value may be quoted
 * with double quotes. Every key may appear once. Unknown keys, duplicates, malformed or
 * out-of-range values and missing required keys are errors, reported as
 *     <file>:<line>: <key> = '<value>': <reason>      or      <file>: missing required key '<key>'
 * The keys, their types, ranges and defaults are in lx_config.c (table s_keys) and in the
 * example firmware/linux_rt/throttle_linux.conf, which lists every key.
 *
 * This module only checks syntax and ranges; whether a path exists, a chip has that line or an
 * interface is a CAN interface is checked when the devices are opened (lx_pwm, lx_adc, lx_gpio,
 * lx_can), and those errors name the key and the value as well.
 */
#ifndef LX_CONFIG_H
#define LX_CONFIG_H

#include <stddef.h>
#include <stdint.h>

#include "can_proto.h"
#include "hal_linux.h"
#include "lx_err.h"

#ifdef __cplusplus
extern "C" {
#endif


/** Everything the configuration file sets. */
typedef struct {
    /* real time */
    int32_t rt_priority;      /**< rt.priority: SCHED_FIFO priority 1..99; 0 = SCHED_OTHER (development only) */
    int32_t rt_cpu;           /**< rt.cpu: CPU the loop thread is pinned to; -1 = not pinned */
    int32_t rt_lock_memory;   /**< rt.lock_memory: 1 = mlockall(MCL_CURRENT | MCL_FUTURE) (required for RT) */
    uint32_t rt_duration_s;   /**< rt.duration_s: stop cleanly after this long; 0 = until SIGINT/SIGTERM */
    uint32_t rt_max_io_errors; /**< rt.max_io_errors: consecutive failed ticks that end the program */
    hal_linux_devices_t dev;      /**< pwm.*, adc.*, gpio.*, can.interface: the devices the HAL opens */
    /* CAN protocol */
    can_proto_config_t can;       /**< can.cmd_timeout_ms, can.max_counter_delta, can.period_ms.* */
    /* start-up control (commands override it at run time) */
    int32_t app_mode;             /**< app.mode: off, sine, steps, chirp, position, ident (app_mode_t) */
    char app_stops_file[LX_PATH_LEN]; /**< app.stops_file: the learned stops and contact law, read at
                                           start (lx_config_overlay_model_file()) and written at a
                                           clean stop (lx_config_write_stops()); "" = none */
    double app_amplitude_V;       /**< app.amplitude_V */
    double app_freq_Hz;           /**< app.freq_Hz */
    double app_chirp_f1_Hz;       /**< app.chirp_f1_Hz */
    double app_chirp_period_s;    /**< app.chirp_period_s */
    double app_target_rad;        /**< app.target_rad */
    double app_duty_limit;        /**< app.duty_limit */
    /* calibration of the analogue front end (defaults: app_calib_default()) */
    double calib_current_offset_counts; /**< calib.current_offset_counts */
    double calib_current_A_per_count;   /**< calib.current_A_per_count */
    double calib_tps1_counts_at_zero;   /**< calib.tps1_counts_at_zero */
    double calib_tps1_rad_per_count;    /**< calib.tps1_rad_per_count */
    double calib_tps2_counts_at_zero;   /**< calib.tps2_counts_at_zero */
    double calib_tps2_rad_per_count;    /**< calib.tps2_rad_per_count */
    double calib_supply_V_per_count;    /**< calib.supply_V_per_count */
    /* the estimator's model (tv_model.h): the keys of a parameter file that identify writes
     * (host_sim/identify/); NaN = not given, the application's default stays */
    double model_R_ohm;           /**< model.R_ohm */
    double model_L_H;             /**< model.L_H */
    double model_Ke_V_s_rad;      /**< model.Ke_V_s_rad */
    double model_Kt_Nm_A;         /**< model.Kt_Nm_A */
    double model_J_kg_m2;         /**< model.J_kg_m2 */
    double model_n_gear;          /**< model.n_gear */
    double model_Mc_Nm;           /**< model.Mc_Nm */
    double model_M0_Nm;           /**< model.M0_Nm */
    double model_c_Nm_rad;        /**< model.c_Nm_rad */
    double model_Kv_Nm_s_rad;     /**< model.Kv_Nm_s_rad */
    double model_Ms_Nm;           /**< model.Ms_Nm */
    double model_ws_rad_s;        /**< model.ws_rad_s */
    double model_phi_closed_rad;  /**< model.phi_closed_rad */
    double model_phi_open_rad;    /**< model.phi_open_rad */
    double model_k_stop_Nm_rad;   /**< model.k_stop_Nm_rad */
    double model_d_stop_Nm_s_rad; /**< model.d_stop_Nm_s_rad */
    double model_stop_exponent;   /**< model.stop_exponent */
    /* what else a parameter file of identify says (host_sim/identify/id_params.h): the start-up
     * stop learning's contact law (stop_learn.h; NaN = not given, the default stays) and the
     * diagnostic bounds relative to the unit's own model (diag_detect_config_identified()) */
    double sl_e_min;              /**< stop_learn.e_min */
    double sl_e_max;              /**< stop_learn.e_max */
    double sl_lambda_per_k_s_rad; /**< stop_learn.lambda_per_k_s_rad */
    double sl_k_min_Nm_rad;       /**< stop_learn.k_min_Nm_rad */
    double sl_k_max_Nm_rad;       /**< stop_learn.k_max_Nm_rad */
    int32_t diag_identified;      /**< diag.identified: 1 = the identified unit's bounds; default 0 */
    double diag_r_fit_high_frac;  /**< diag.r_fit_high_frac (NaN = not given: the default bound) */
    double diag_friction_high_rel; /**< diag.friction_high_rel (NaN = not given: the default bound) */
    double diag_friction_fast_high; /**< diag.friction_fast_high (NaN = not given: the default bound) */
    double diag_friction_fast_level_min; /**< diag.friction_fast_level_min (NaN = not given: the default) */
    double diag_fit_base_r_ohm;   /**< diag.fit_base_r_ohm: the fit's per-unit baseline (NaN = not given: none) */
    double diag_fit_base_nke_V_s; /**< diag.fit_base_nke_V_s (NaN = not given: none) */
    uint16_t diag_fit_base_windows; /**< diag.fit_base_windows: learn the baseline over this many windows; default 0 */
    double diag_r_fit_base_high_frac; /**< diag.r_fit_base_high_frac (NaN = not given: the default bound) */
    double diag_gain_fit_base_max; /**< diag.gain_fit_base_max (NaN = not given: the default bound) */
} lx_config_t;

/** Fill *cfg with every default (required keys empty / zero). */
void lx_config_default(lx_config_t *cfg);

/**
 * Parse configuration text (the contents of a file) into *cfg, on top of lx_config_default().
 * @param text   NUL-terminated text
 * @param name   name used in error messages (the file name)
 * @param err    receives the error message (may be NULL), always NUL-terminated
 * @return TV_OK; TV_ERR_NULL; TV_ERR_FORMAT (syntax, unknown or duplicate key, line too long);
 *         TV_ERR_RANGE (a value outside its range); TV_ERR_CONFIG (a required key missing, or
 *         two keys in conflict, e.g. the same channel twice). On error *cfg is unspecified.
 */
int lx_config_parse(const char *text, const char *name, lx_config_t *cfg, char *err, size_t err_len);

/**
 * Read and parse a file (at most 64 KiB).
 * @return as lx_config_parse(); TV_ERR_IO when the file cannot be read (message names it).
 */
int lx_config_load(const char *path, lx_config_t *cfg, char *err, size_t err_len);

/**
 * Apply the control and calibration keys to an application configuration (from
 * app_config_default()); the application validates the result in app_init().
 */
void lx_config_apply_app(const lx_config_t *cfg, app_config_t *app);

/**
 * Overlay a file of model.* keys (the stops file, or a parameter file's model lines) onto cfg:
 * only keys beginning with "model." are allowed, none is required, each at most once, ranges as
 * in the configuration; what the file does not set is left as it is.
 * @return TV_OK; TV_ERR_IO when the file cannot be opened or read (err says why; errno is kept,
 *         so ENOENT tells a file not written yet); TV_ERR_FORMAT / TV_ERR_RANGE / TV_ERR_CONFIG
 *         on bad content (err names the file and line).
 */
int lx_config_overlay_model_file(const char *path, lx_config_t *cfg, char *err, size_t err_len);

/** lx_config_overlay_model_file() on text already in memory (name is used in the messages). */
int lx_config_overlay_model(const char *text, const char *name, lx_config_t *cfg, char *err, size_t err_len);

/**
 * Write the stops file: model.phi_closed_rad, model.phi_open_rad, model.k_stop_Nm_rad,
 * model.stop_exponent, model.d_stop_Nm_s_rad (%.9g), and the fit's per-unit baseline
 * diag.fit_base_r_ohm, diag.fit_base_nke_V_s when both are positive (0: none yet, not written), to
 * path + ".tmp", flushed and synced, then renamed over path, so a crash leaves the old file or the
 * new one, never half of one.
 * @return TV_OK; TV_ERR_NONFINITE; TV_ERR_IO (err names the file and the reason).
 */
int lx_config_write_stops(const char *path, double phi_closed_rad, double phi_open_rad, double k_stop,
                          double stop_exponent, double d_stop, double fit_base_r_ohm, double fit_base_nke_V_s, char *err,
                          size_t err_len);

#ifdef __cplusplus
}
#endif

#endif /* LX_CONFIG_H */
