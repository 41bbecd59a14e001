/**
 * @file replay.c
 * @brief Replay of raw ADC logs through app_step() in APP_MODE_EXTERNAL (see replay.h).
 */
#define _POSIX_C_SOURCE 200809L

#include "replay.h"

#include <math.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "diag_csv.h"
#include "numfmt.h"
#include "tv_status.h"

/* ADC resolution the default count limits are written for. */
#define REPLAY_LIMITS_ADC_FULL 4096.0
/* Progress: look at the clock every this many samples, print at most this often [s]. */
#define REPLAY_PROGRESS_EVERY 4096u
#define REPLAY_PROGRESS_PERIOD_S 0.25
/* Largest output line [bytes]. */
#define REPLAY_LINE_MAX 1024u
/* Output buffer of the stream [bytes]. */
#define REPLAY_OUT_BUF 262144u

static const char s_columns[] =
    "t_us,duty,bridge_enable,i_est_A,w_est_rad_s,phi_est_rad,i_sigma_A,w_sigma_rad_s,phi_sigma_rad,innov_i_A,"
    "innov_w_rad_s,innov_phi_rad,nis,nis_dof,faults,ekf_status,missing_samples";
static const char s_wide_columns[] =
    ",i_meas_A,w_meas_rad_s,phi_meas_rad,supply_V,innov_i_sigma_A,innov_w_sigma_rad_s,innov_phi_sigma_rad,"
    "R_est_ohm,R_sigma_ohm,friction_rel,friction_rel_sigma,preload_rel,preload_rel_sigma,R_fit_ohm,R_fit_sigma_ohm,"
    "nKe_fit_V_s_rad,nKe_fit_sigma_V_s_rad,i_off_fit_A,i_off_fit_sigma_A";
static const char s_truth_columns[] = ",i_true_A,w_true_rad_s,phi_true_rad";

void replay_options_default(replay_options_t *o)
{
    if (o == NULL) {
        return;
    }
    memset(o, 0, sizeof *o);
    o->setup = EKF_SETUP_CURRENT_ANGLE;
    o->max_messages = REPLAY_MESSAGES_DEFAULT;
}

static double now_s(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void note(const replay_options_t *o, const char *text)
{
    if (o->diag != NULL) {
        fprintf(o->diag, "%s\n", text);
    }
}

/* tv_real_t of a calibration value, failing when the scalar type cannot hold it. */
static int calib_real(double v, tv_real_t *out)
{
    const tv_real_t r = (tv_real_t)v;
    if (!TV_IS_FINITE(r) || (v != 0.0 && r == TV_R(0.0))) {
        return TV_ERR_CONFIG;
    }
    *out = r;
    return TV_OK;
}

static tv_real_t *calib_field(app_calib_t *c, int k)
{
    switch (k) {
    case 0: return &c->current_offset_counts;
    case 1: return &c->current_A_per_count;
    case 2: return &c->tps1_counts_at_zero;
    case 3: return &c->tps1_rad_per_count;
    case 4: return &c->tps2_counts_at_zero;
    case 5: return &c->tps2_rad_per_count;
    default: return &c->supply_V_per_count;
    }
}

/* Scale a 12-bit count limit to another resolution. */
static uint16_t scale_limit(uint16_t lim, uint32_t adc_max)
{
    const double v = floor((double)lim * ((double)adc_max + 1.0) / REPLAY_LIMITS_ADC_FULL + 0.5);
    return (uint16_t)(v > (double)adc_max ? (double)adc_max : v);
}

int replay_build_config(const rlr_t *r, const replay_options_t *o, app_config_t *cfg, char *err, size_t cap)
{
    app_config_t c;
    const uint32_t rate_Hz = 1000000u / APP_PERIOD_US;
    int k;
    if (r == NULL || o == NULL || cfg == NULL) {
        return TV_ERR_NULL;
    }
    app_config_default(&c);
    if (r->hdr.sample_rate_Hz != rate_Hz) {
        (void)snprintf(err, cap, "%s: the log's sample rate is %lu Hz; the application runs at %lu Hz", r->name,
                       (unsigned long)r->hdr.sample_rate_Hz, (unsigned long)rate_Hz);
        return TV_ERR_CONFIG;
    }
    c.calib.adc_max_counts = (uint16_t)r->adc_max_counts;
    if (r->adc_max_counts != 4095u) {
        c.limits.current_min_counts = scale_limit(c.limits.current_min_counts, r->adc_max_counts);
        c.limits.current_max_counts = scale_limit(c.limits.current_max_counts, r->adc_max_counts);
        c.limits.tps_min_counts = scale_limit(c.limits.tps_min_counts, r->adc_max_counts);
        c.limits.tps_max_counts = scale_limit(c.limits.tps_max_counts, r->adc_max_counts);
    }
    for (k = 0; k < RLR_NCAL; ++k) {
        const char *key = rlr_calib_name(k);
        char pkey[64];
        (void)snprintf(pkey, sizeof pkey, "calib.%s", key);
        if ((r->calib_present & (1u << k)) != 0u) {
            if (calib_real(rlr_calib_value(&r->hdr, k), calib_field(&c.calib, k)) != TV_OK) {
                (void)snprintf(err, cap, "%s: calibration %s = %.17g cannot be represented in this build's scalar type",
                               r->name, key, rlr_calib_value(&r->hdr, k));
                return TV_ERR_CONFIG;
            }
        } else if (!params_is_set(o->params, pkey) && o->diag != NULL) {
            fprintf(o->diag, "replay: note: %s gives no %s: using the default %.9g\n", r->name, key,
                    (double)*calib_field(&c.calib, k));
        }
    }
    if (o->params != NULL) {
        const int rc = params_apply(o->params, &c, err, cap);
        if (rc != TV_OK) {
            return rc;
        }
    }
    c.ekf.setup = o->setup;
    c.control.mode = APP_MODE_EXTERNAL;
    *cfg = c;
    return TV_OK;
}

/* Where calibration value k of a run came from: "FILE:LINE: calib.KEY" of the parameter file,
 * the log's metadata line or binary header, or the default. */
static void calib_source(const rlr_t *r, const replay_options_t *o, int k, char *out, size_t cap)
{
    char pkey[64];
    const int pk = (snprintf(pkey, sizeof pkey, "calib.%s", rlr_calib_name(k)), params_key_index(pkey));
    if (o->params != NULL && pk >= 0 && o->params->line[pk] != 0u) {
        (void)snprintf(out, cap, "%s:%lu: %s", o->params->file, (unsigned long)o->params->line[pk], pkey);
    } else if ((r->calib_present & (1u << k)) != 0u && r->calib_line[k] != 0u) {
        (void)snprintf(out, cap, "%s:%llu: metadata %s", r->name, (unsigned long long)r->calib_line[k],
                       rlr_calib_name(k));
    } else if ((r->calib_present & (1u << k)) != 0u) {
        (void)snprintf(out, cap, "%s: binary header field %s", r->name, rlr_calib_name(k));
    } else {
        (void)snprintf(out, cap, "%s (default: %s gives none)", rlr_calib_name(k), r->name);
    }
}

/* Why app_init() refused cfg, naming the value and where it came from (file, line, key). */
static void explain_config(const rlr_t *r, const replay_options_t *o, const app_config_t *c, int rc, char *err,
                           size_t cap)
{
    const app_calib_t *k = &c->calib;
    const app_limits_t *l = &c->limits;
    const char *why = "the model or noise parameters are invalid (tvm_init / ekf_init)";
    int bad = -1; /* calibration index */
    if (!(k->current_A_per_count != TV_R(0.0))) {
        why = "must not be 0";
        bad = 1;
    } else if (!(k->tps1_rad_per_count > TV_R(0.0))) {
        why = "must be > 0 (rising track)";
        bad = 3;
    } else if (!(k->tps2_rad_per_count < TV_R(0.0))) {
        why = "must be < 0 (falling track)";
        bad = 5;
    } else if (!(k->supply_V_per_count > TV_R(0.0))) {
        why = "must be > 0";
        bad = 6;
    } else if (l->current_max_counts > k->adc_max_counts || l->tps_max_counts > k->adc_max_counts) {
        why = "a count limit exceeds the ADC range of the log";
    } else if (l->current_min_counts >= l->current_max_counts || l->tps_min_counts >= l->tps_max_counts) {
        why = "a count limit's minimum is not below its maximum";
    }
    if (bad >= 0) {
        char where[PARAMS_NAME_MAX + 96];
        app_calib_t copy = c->calib;
        calib_source(r, o, bad, where, sizeof where);
        (void)snprintf(err, cap, "the application rejects the configuration (%s): %s = %.9g %s", tv_status_str(rc),
                       where, (double)*calib_field(&copy, bad), why);
    } else {
        (void)snprintf(err, cap, "the application rejects the configuration (%s): %s", tv_status_str(rc), why);
    }
}

/* Seconds to whole microseconds, rounded, saturating (NaN and negatives: 0). */
static uint64_t seconds_to_us(double s)
{
    const double us = floor(s * 1e6 + 0.5);
    if (!(us > 0.0)) {
        return 0u;
    }
    return us >= 18446744073709549568.0 ? UINT64_MAX : (uint64_t)us;
}

/* Append helpers for one output line. */
static size_t put_g(char *p, double v)
{
    p[0] = ',';
    return 1u + numfmt_g9(p + 1, v);
}

static size_t put_u(char *p, uint64_t v)
{
    p[0] = ',';
    return 1u + numfmt_u64(p + 1, v);
}

static size_t format_line(char *line, const rawlog_record_t *rec, const app_output_t *out, const vfit_t *fit,
                          const replay_options_t *o, int truth)
{
    size_t n = numfmt_u64(line, rec->t_us);
    int a;
    n += put_g(line + n, (double)rec->duty);
    n += put_u(line + n, rec->bridge_enable);
    for (a = 0; a < TVM_NX; ++a) {
        n += put_g(line + n, (double)out->x[a]);
    }
    for (a = 0; a < TVM_NX; ++a) {
        n += put_g(line + n, (double)out->sigma[a]);
    }
    for (a = 0; a < EKF_NCH; ++a) {
        if (out->innov.used[a]) {
            n += put_g(line + n, (double)out->innov.innov[a]);
        } else {
            line[n++] = ',';
        }
    }
    if (out->innov.n_used > 0u) {
        n += put_g(line + n, (double)out->innov.nis_total);
    } else {
        line[n++] = ',';
    }
    n += put_u(line + n, out->innov.n_used);
    n += put_u(line + n, out->faults);
    line[n++] = ',';
    n += numfmt_i64(line + n, out->ekf_status);
    n += put_u(line + n, out->missing_samples);
    if (o->wide) {
        for (a = 0; a < EKF_NCH; ++a) {
            n += put_g(line + n, (double)out->z[a]);
        }
        n += put_g(line + n, (double)out->supply_V);
        for (a = 0; a < EKF_NCH; ++a) {
            if (out->innov.used[a]) {
                n += put_g(line + n, sqrt((double)out->innov.innov_var[a]));
            } else {
                line[n++] = ',';
            }
        }
        n += put_g(line + n, (double)out->r_est_ohm);
        n += put_g(line + n, (double)out->r_sigma_ohm);
        n += put_g(line + n, (double)out->friction_rel);
        n += put_g(line + n, (double)out->friction_rel_sigma);
        n += put_g(line + n, (double)out->preload_rel);
        n += put_g(line + n, (double)out->preload_rel_sigma);
        if (fit->valid) {
            /* the voltage equation's fit (volt_fit.h): its last window taken */
            n += put_g(line + n, (double)fit->r_ohm);
            n += put_g(line + n, (double)fit->r_sigma_ohm);
            n += put_g(line + n, (double)fit->nke_V_s);
            n += put_g(line + n, (double)fit->nke_sigma_V_s);
        } else {
            for (a = 0; a < 4; ++a) {
                line[n++] = ',';
            }
        }
        if (fit->off_valid) {
            /* ... and the current measurement's offset from its fit with an intercept */
            n += put_g(line + n, (double)fit->i_off_A);
            n += put_g(line + n, (double)fit->i_off_sigma_A);
        } else {
            line[n++] = ',';
            line[n++] = ',';
        }
    }
    if (truth) {
        for (a = 0; a < 3; ++a) {
            n += put_g(line + n, rec->truth[a]);
        }
    }
    line[n++] = '\n';
    return n;
}

/* Column header first (numpy.genfromtxt(names=True) takes the first line), then comments. */
static int write_header(const rlr_t *r, const replay_options_t *o)
{
    FILE *f = o->out;
    fputs(s_columns, f);
    if (o->wide) {
        fputs(s_wide_columns, f);
    }
    if (r->has_truth) {
        fputs(s_truth_columns, f);
    }
    fputc('\n', f);
    fprintf(f, "# replay of %s (%s, %lu Hz, %u-bit ADC) through the firmware's app_step() in APP_MODE_EXTERNAL, "
               "%s build, measurement set-up %d%s%s\n",
            r->name, rlr_format_name(r->format), (unsigned long)r->hdr.sample_rate_Hz, (unsigned)r->hdr.adc_bits,
            TV_REAL_IS_DOUBLE ? "double" : "float", o->setup == EKF_SETUP_PAPER_3MEAS ? 3 : 2,
            o->params_name != NULL ? ", parameters " : "", o->params_name != NULL ? o->params_name : "");
    fputs("# units: t_us [us]; duty [-1, 1]; *_A [A]; *_rad_s [rad/s]; *_rad [rad]; *_V [V]; sigma = standard "
          "deviation; innov = measurement - prediction (empty: channel not used); nis = normalised innovation "
          "squared, nis_dof channels (empty: no correction); faults = APP_FAULT_* mask (firmware/app/app.h); "
          "ekf_status = tv_status_t of the step; missing_samples predicted across before this sample\n",
          f);
    return ferror(f) ? TV_ERR_IO : TV_OK;
}

/* Print an input error, at most max_messages per class. */
static void report_error(const rlr_t *r, const replay_options_t *o, uint64_t count_in_class)
{
    if (o->diag == NULL) {
        return;
    }
    if (count_in_class <= o->max_messages) {
        fprintf(o->diag, "replay: %s%s\n", rlr_message(r),
                o->skip_errors && rlr_recoverable(r) ? " [skipped]" : "");
    }
    if (count_in_class == o->max_messages && o->skip_errors && rlr_recoverable(r)) {
        fprintf(o->diag, "replay: (further '%s' messages are not shown; the summary counts them)\n",
                rlr_err_name(rlr_error(r)));
    }
}

int replay_run(rlr_t *r, const replay_options_t *o, replay_stats_t *st)
{
    app_t app;
    app_config_t cfg;
    rawlog_record_t rec;
    app_output_t out;
    char err[PARAMS_MSG_MAX + 128];
    char line[REPLAY_LINE_MAX];
    const double t_begin = now_s();
    double t_last_progress = t_begin;
    int progress_shown = 0;
    uint64_t start_us;
    uint64_t stop_us;
    int rc;
    if (r == NULL || o == NULL || st == NULL) {
        return TV_ERR_NULL;
    }
    memset(st, 0, sizeof *st);
    memset(&out, 0, sizeof out);
    /* the time window in whole microseconds (no rounding surprises at the boundaries) */
    start_us = o->has_start ? seconds_to_us(o->start_s) : 0u;
    stop_us = o->has_stop ? seconds_to_us(o->stop_s) : 0u;
    err[0] = '\0';
    rc = TV_OK;
    if (!o->parse_only) { /* validating a log needs no application */
        rc = replay_build_config(r, o, &cfg, err, sizeof err);
        if (rc == TV_OK) {
            rc = app_init(&app, &cfg);
            if (rc != TV_OK) {
                explain_config(r, o, &cfg, rc, err, sizeof err);
            }
        }
        if (rc == TV_OK && o->temp_known) {
            rc = app_set_winding_temp(&app, 1, (tv_real_t)o->winding_temp_C);
            if (rc != TV_OK) {
                (void)snprintf(err, sizeof err, "winding temperature %g degC: outside %g .. %g degC", o->winding_temp_C,
                               APP_WINDING_TEMP_MIN_C, APP_WINDING_TEMP_MAX_C);
            }
        }
    }
    if (rc != TV_OK) {
        st->config_error = 1;
        if (o->diag != NULL) {
            fprintf(o->diag, "replay: %s\n", err);
        }
        return TV_ERR_CONFIG;
    }
    if (o->out != NULL && !o->parse_only) {
        rc = write_header(r, o);
        if (rc != TV_OK) {
            st->io_error = 1;
            return rc;
        }
    }
    for (;;) {
        rc = rlr_next(r, &rec);
        if (rc == 0) {
            break;
        }
        if (rc < 0) {
            const rlr_err_t e = rlr_error(r);
            report_error(r, o, r->st.errors[e]);
            if (!o->skip_errors || !rlr_recoverable(r)) {
                st->stop_err = e;
                break;
            }
            ++st->skipped;
            continue;
        }
        if (o->has_stop && rec.t_us > stop_us) {
            st->stopped_at_stop = 1;
            break;
        }
        if (o->has_start && rec.t_us < start_us) {
            ++st->before_start;
            continue;
        }
        if (st->replayed > 0u) {
            const uint64_t gap = rlr_last_gap(r);
            if (gap > 0u) {
                st->missing_samples += gap;
                ++st->gaps;
                if (gap >= 100u) {
                    ++st->gaps_over_limit;
                }
                if (st->gaps <= o->max_messages && o->diag != NULL) {
                    char loc[96];
                    rlr_where(r, loc, sizeof loc);
                    fprintf(o->diag, "replay: note: %s: %s: %llu samples missing before t_us %llu (%s)\n", r->name,
                            loc, (unsigned long long)gap, (unsigned long long)rec.t_us,
                            gap < 100u ? "predicted across" : "longer than the 100 periods predicted across: APP_FAULT_TIMING");
                }
            }
        } else {
            st->first_t_us = rec.t_us;
        }
        st->last_t_us = rec.t_us;
        ++st->replayed;
        if (!o->parse_only) {
            app_input_t in;
            int a;
            for (a = 0; a < 4; ++a) {
                in.adc[a] = rec.adc[a];
            }
            in.t_us = rec.t_us;
            in.driver_fault = rec.driver_fault;
            in.duty_ext = rec.duty;
            in.bridge_ext = rec.bridge_enable;
            if (o->timing) {
                const double t0 = now_s();
                app_step(&app, &in, &out);
                st->estimator_s += now_s() - t0;
            } else {
                app_step(&app, &in, &out);
            }
            if (out.faults != 0u) {
                ++st->fault_samples;
            }
            if (out.ekf_status != TV_OK) {
                ++st->ekf_rejections;
            }
            st->faults = out.faults;
            st->dtc_active = out.dtc_confirmed;
            {
                /* the diagnostic events of this step (the application's queue, drained every sample) */
                diag_event_t ev;
                while (diag_event_pop(&app.diag, &ev)) {
                    ++st->dtc_events;
                    if (ev.kind == DIAG_EV_CONFIRMED && ((st->dtc_ever >> ev.dtc) & 1u) == 0u) {
                        st->dtc_ever |= 1u << ev.dtc;
                        st->dtc_first_us[ev.dtc] = ev.t_us;
                    }
                    if (o->events != NULL && diag_csv_event(o->events, &ev) != TV_OK) {
                        st->io_error = 1;
                    }
                }
                st->dtc_events_lost = app.diag.events_lost;
            }
            if (o->out != NULL) {
                const double t0 = o->timing ? now_s() : 0.0;
                const size_t n = format_line(line, &rec, &out, &app.vfit, o, r->has_truth);
                if (fwrite(line, 1u, n, o->out) != n) {
                    st->io_error = 1;
                    break;
                }
                if (o->timing) {
                    st->output_s += now_s() - t0;
                }
            }
            if (o->on_sample != NULL) {
                o->on_sample(&rec, &out, o->user);
            }
        }
        if (o->progress && o->diag != NULL && (st->replayed % REPLAY_PROGRESS_EVERY) == 0u) {
            const double t = now_s();
            if (t - t_last_progress >= REPLAY_PROGRESS_PERIOD_S) {
                t_last_progress = t;
                progress_shown = 1;
                fprintf(o->diag, "\rreplay: %llu samples, log time %.1f s ", (unsigned long long)st->replayed,
                        (double)rec.t_us * 1e-6);
                fflush(o->diag);
            }
        }
    }
    if (progress_shown) {
        fputc('\n', o->diag);
    }
    if (o->out != NULL && !o->parse_only && fflush(o->out) != 0) {
        st->io_error = 1;
    }
    st->total_s = now_s() - t_begin;
    {
        struct rusage ru;
        if (getrusage(RUSAGE_SELF, &ru) == 0) {
            st->max_rss_kib = ru.ru_maxrss; /* KiB on Linux */
        }
    }
    if (st->io_error) {
        note(o, "replay: writing the output failed");
        return TV_ERR_IO;
    }
    return TV_OK;
}

int replay_exit_code(const replay_stats_t *st)
{
    if (st == NULL) {
        return RLR_EXIT_IO;
    }
    if (st->io_error) {
        return RLR_EXIT_IO;
    }
    if (st->config_error) {
        return RLR_EXIT_CONFIG;
    }
    if (st->stop_err != RLR_E_NONE) {
        return rlr_exit_code(st->stop_err);
    }
    return st->skipped > 0u ? RLR_EXIT_SKIPPED : RLR_EXIT_OK;
}

/* The diagnostic codes confirmed during the replay, with their first times. */
static void replay_print_codes(FILE *f, const replay_stats_t *st)
{
    int k;
    fprintf(f, "replay: diagnostic codes confirmed:");
    for (k = 0; k < (int)DIAG_DTC_COUNT; ++k) {
        if ((st->dtc_ever >> k) & 1u) {
            const diag_dtc_info_t *i = diag_dtc_info((diag_dtc_t)k);
            fprintf(f, " %s (%s) at t = %.6f s%s;", i->code, i->fault_class, (double)st->dtc_first_us[k] * 1e-6,
                    (st->dtc_active >> k) & 1u ? "" : ", healed since");
        }
    }
    fprintf(f, "%s (%llu events, %lu lost)\n", st->dtc_ever == 0u ? " none" : "", (unsigned long long)st->dtc_events,
            (unsigned long)st->dtc_events_lost);
}

void replay_print_summary(FILE *f, const rlr_t *r, const replay_stats_t *st, const replay_options_t *o)
{
    if (f == NULL || r == NULL || st == NULL || o == NULL) {
        return;
    }
    fprintf(f, "replay: %s (%s): %llu records read, %llu samples %s", r->name, rlr_format_name(r->format),
            (unsigned long long)r->st.records, (unsigned long long)st->replayed,
            o->parse_only ? "validated" : "replayed");
    if (st->replayed > 0u) {
        fprintf(f, " (t = %.6f .. %.6f s)", (double)st->first_t_us * 1e-6, (double)st->last_t_us * 1e-6);
    }
    fputc('\n', f);
    if (st->before_start > 0u || st->stopped_at_stop) {
        fprintf(f, "replay: time window: %llu samples before the start time not replayed%s\n",
                (unsigned long long)st->before_start, st->stopped_at_stop ? "; stopped at the stop time" : "");
    }
    fprintf(f, "replay: gaps: %llu, missing samples: %llu (predicted across)", (unsigned long long)st->gaps,
            (unsigned long long)st->missing_samples);
    if (st->gaps_over_limit > 0u) {
        fprintf(f, "; %llu gaps longer than 100 periods (APP_FAULT_TIMING)", (unsigned long long)st->gaps_over_limit);
    }
    if (r->format == RLR_FMT_BIN && r->st.blocks_missing > 0u) {
        fprintf(f, "; %llu blocks missing from the sequence numbers", (unsigned long long)r->st.blocks_missing);
    }
    fputc('\n', f);
    {
        uint64_t total = 0;
        int e;
        for (e = 1; e < (int)RLR_E_COUNT; ++e) {
            total += r->st.errors[e];
        }
        if (total > 0u) {
            fprintf(f, "replay: input errors%s:", o->skip_errors ? " (skipped)" : "");
            for (e = 1; e < (int)RLR_E_COUNT; ++e) {
                if (r->st.errors[e] > 0u) {
                    fprintf(f, " %s %llu;", rlr_err_name((rlr_err_t)e), (unsigned long long)r->st.errors[e]);
                }
            }
            fputc('\n', f);
        } else {
            fputs("replay: input errors: none\n", f);
        }
    }
    if (!o->parse_only) {
        fprintf(f, "replay: faults latched 0x%03lx (%llu samples with a fault), EKF rejections %llu\n",
                (unsigned long)st->faults, (unsigned long long)st->fault_samples,
                (unsigned long long)st->ekf_rejections);
        replay_print_codes(f, st);
    }
    if (st->stop_err != RLR_E_NONE) {
        fprintf(f, "replay: stopped at the first error (%s): exit %d%s\n", rlr_err_name(st->stop_err),
                rlr_exit_code(st->stop_err),
                rlr_recoverable(r) ? "; --on-error skip skips such input and goes on" : "");
    }
    if (o->timing) {
        const double rate = st->total_s > 0.0 ? (double)st->replayed / st->total_s : 0.0;
        fprintf(f, "replay: timing: %.3f s total, %.0f samples/s; app_step %.3f s (%.1f %%), output %.3f s, "
                   "reading+parsing+rest %.3f s; outside the estimator %.1f %%; peak RSS %ld KiB\n",
                st->total_s, rate, st->estimator_s, st->total_s > 0.0 ? 100.0 * st->estimator_s / st->total_s : 0.0,
                st->output_s, st->total_s - st->estimator_s - st->output_s,
                st->total_s > 0.0 ? 100.0 * (1.0 - st->estimator_s / st->total_s) : 0.0, st->max_rss_kib);
    }
}
