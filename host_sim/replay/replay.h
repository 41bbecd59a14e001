/**
 * @file replay.h
 * @brief Replay of a logged raw ADC stream through the firmware's own application step: the
 *        count conversion, the plausibility checks and the EKF of app_step(), in
 *        APP_MODE_EXTERNAL with the LOGGED duty and bridge enable (the log comes from another
 *        controller, or from host_sim). Streaming: one record in, one CSV line out, constant
 *        memory whatever the length of the log.
 *
 * CONFIGURATION of the application (replay_build_config()), later steps overriding earlier:
 *   1. app_config_default();
 *   2. the log's header: sample rate (must be the application's 1000 Hz), ADC resolution
 *      (calib.adc_max_counts; the count limits are scaled from 12 bits when it differs) and
 *      the calibration values the log carries (all of them in binary; those in the metadata of
 *      a CSV log, the others keep the defaults with a note);
 *   3. the parameter settings (params.h: a file, then command-line overrides such as Q and R);
 *   4. the measurement set-up; control mode APP_MODE_EXTERNAL.
 * With the same configuration and the same records, replay_run() computes exactly what the
 * live application computed (bit for bit: tests/test_replay_roundtrip.c).
 *
 * OUTPUT (CSV, one line per replayed sample; numbers %.9g, exact integers):
 *   t_us, duty, bridge_enable, i_est_A, w_est_rad_s, phi_est_rad, i_sigma_A, w_sigma_rad_s,
 *   phi_sigma_rad, innov_i_A, innov_w_rad_s, innov_phi_rad, nis, nis_dof, faults, ekf_status,
 *   missing_samples  [wide: i_meas_A, w_meas_rad_s, phi_meas_rad, supply_V, innov_i_sigma_A,
 *   innov_w_sigma_rad_s, innov_phi_sigma_rad]  [truth in the log: i_true_A, w_true_rad_s,
 *   phi_true_rad]. Innovations of unused channels and the NIS of a step without correction are
 *   empty fields (NaN for numpy / pandas). sigma = sqrt(P_ii) after the step.
 *
 * BAD INPUT: every reader error (rawlog_read.h) is printed (the first max_messages of each
 * class, then a count) with the file and line / byte offset; by default the first one stops
 * the replay, with skip_errors the bad line / record / block is skipped, counted, and the
 * replay goes on (fatal header errors always stop). Gaps are predicted across by app_step()
 * (up to 100 periods; beyond, APP_FAULT_TIMING latches) and reported.
 */
#ifndef REPLAY_H
#define REPLAY_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "app.h"
#include "params.h"
#include "rawlog_read.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Default number of messages printed per error class (and of gap notes). */
#define REPLAY_MESSAGES_DEFAULT 10u

/** Called once per replayed sample (tests: exact comparison with a live run). */
typedef void (*replay_sample_fn)(const rawlog_record_t *rec, const app_output_t *out, void *user);

/** What to do. Initialise with replay_options_default(). */
typedef struct {
    ekf_setup_t setup;          /**< measurement set-up, default EKF_SETUP_CURRENT_ANGLE */
    const params_t *params;     /**< NULL, or parameter settings (file + overrides) */
    int has_start;              /**< 1: replay from start_s */
    double start_s;             /**< first log time replayed [s] (t_us >= start_s * 1e6 rounded to 1 us), >= 0 */
    int has_stop;               /**< 1: stop after stop_s */
    double stop_s;              /**< last log time replayed [s] (t_us <= stop_s * 1e6 rounded), >= 0 */
    int skip_errors;            /**< 0: stop at the first input error; 1: skip and count */
    int parse_only;             /**< 1: read and validate only (no estimator, no output) */
    int wide;                   /**< 1: also measurements, supply, innovation sigmas */
    FILE *out;                  /**< output CSV stream, NULL for none */
    FILE *events;               /**< NULL, or a stream for the diagnostic events (diag_csv.h: t_us,status,fault_class,dtc) */
    FILE *diag;                 /**< messages and summary (stderr), NULL for silence */
    unsigned max_messages;      /**< messages per error class, and gap notes */
    int progress;               /**< 1: a progress line on diag (the tool sets it when diag is a tty) */
    int timing;                 /**< 1: measure the time inside app_step() */
    int temp_known;             /**< 1: the application is told winding_temp_C (app_set_winding_temp()) */
    double winding_temp_C;      /**< the winding's temperature during the log [degC] (with temp_known) */
    const char *params_name;    /**< parameter file name for the output's comment (NULL: none) */
    replay_sample_fn on_sample; /**< NULL, or called per replayed sample */
    void *user;                 /**< passed to on_sample */
} replay_options_t;

/** What happened. */
typedef struct {
    uint64_t replayed;          /**< samples through app_step() (or validated, with parse_only) */
    uint64_t before_start;      /**< valid records before start_s (not replayed) */
    uint64_t skipped;           /**< input errors skipped (lines, records, blocks) */
    uint64_t missing_samples;   /**< samples missing in gaps between replayed samples */
    uint64_t gaps;              /**< number of those gaps */
    uint64_t gaps_over_limit;   /**< gaps longer than the application predicts across */
    uint64_t fault_samples;     /**< samples with any fault latched */
    uint64_t ekf_rejections;    /**< samples whose EKF step was rejected (ekf_status != 0) */
    uint32_t faults;            /**< latched fault mask at the end (APP_FAULT_*) */
    uint64_t dtc_events;        /**< diagnostic events of the application (firmware/diag/diag.h) */
    uint32_t dtc_events_lost;   /**< events its queue dropped */
    uint32_t dtc_ever;          /**< codes confirmed at some time (bit per diag_dtc_t) */
    uint32_t dtc_active;        /**< codes confirmed at the end */
    uint64_t dtc_first_us[DIAG_DTC_COUNT]; /**< each code's first confirmation [us] (valid where dtc_ever has its bit) */
    uint64_t first_t_us;        /**< time of the first replayed sample */
    uint64_t last_t_us;         /**< time of the last replayed sample */
    int stopped_at_stop;        /**< 1: the stop time ended the replay */
    rlr_err_t stop_err;         /**< input error that stopped the replay (RLR_E_NONE if none) */
    int config_error;           /**< 1: the configuration was rejected (nothing replayed) */
    int io_error;               /**< 1: writing the output failed */
    double total_s;             /**< wall time of replay_run() [s] */
    double estimator_s;         /**< time inside app_step() [s] (with timing) */
    double output_s;            /**< time formatting and writing the output [s] (with timing) */
    long max_rss_kib;           /**< peak resident set size of the process [KiB] (getrusage) */
} replay_stats_t;

/** Defaults: set-up 2 (current + angle), whole log, stop on errors, narrow output, no streams. */
void replay_options_default(replay_options_t *o);

/**
 * The application configuration for a log (see the file comment).
 * @param err receives the reason on error
 * @return 0; TV_ERR_NULL; TV_ERR_CONFIG (sample rate not 1000 Hz, a calibration value the
 *         scalar type cannot hold); params_apply()'s status.
 */
int replay_build_config(const rlr_t *r, const replay_options_t *o, app_config_t *cfg, char *err, size_t cap);

/**
 * Replay an opened log to the end (or to the stop time, or to the first error unless skipping).
 * @return 0 (check st->stop_err, st->skipped); TV_ERR_NULL; TV_ERR_CONFIG (st->config_error,
 *         message on diag); TV_ERR_IO (output write failed).
 */
int replay_run(rlr_t *r, const replay_options_t *o, replay_stats_t *st);

/** The tool's exit code for a run (RLR_EXIT_*, or rlr_exit_code() of the stopping error). */
int replay_exit_code(const replay_stats_t *st);

/** Print the closing summary (counts of everything read, skipped, missing; faults). */
void replay_print_summary(FILE *f, const rlr_t *r, const replay_stats_t *st, const replay_options_t *o);

#ifdef __cplusplus
}
#endif

#endif /* REPLAY_H */
