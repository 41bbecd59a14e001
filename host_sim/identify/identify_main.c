/**
 * @file identify_main.c
 * @brief identify: estimate the model's parameters from one raw log and write them as a
 *        parameter file (see usage() and identify.h).
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli.h"
#include "id_params.h"
#include "identify.h"
#include "params.h"
#include "replay.h"
#include "tv_status.h"

static const char *s_prog = "identify";

#define usage_error(...) cli_usage_error(s_prog, __VA_ARGS__)

/** Exit code: the log does not move the plate enough to identify the plate's parameters. */
#define ID_EXIT_EXCITATION 20

/* The reader and the parameters are large: static, one run per process. */
static rlr_t s_reader;
static params_t s_params;

/* The samples, grown as the log is read. */
typedef struct {
    size_t n, cap;
    double *u, *i, *phi;
    uint8_t *ok;
    uint64_t last_t_us;
    int have_last;
    int oom;
} samples_t;

static void samples_free(samples_t *s)
{
    free(s->u);
    free(s->i);
    free(s->phi);
    free(s->ok);
}

static int samples_grow(samples_t *s)
{
    const size_t cap = s->cap == 0u ? 65536u : 2u * s->cap;
    double *u = (double *)realloc(s->u, cap * sizeof *u);
    double *i;
    double *phi;
    uint8_t *ok;
    if (u == NULL) {
        return -1;
    }
    s->u = u;
    i = (double *)realloc(s->i, cap * sizeof *i);
    if (i == NULL) {
        return -1;
    }
    s->i = i;
    phi = (double *)realloc(s->phi, cap * sizeof *phi);
    if (phi == NULL) {
        return -1;
    }
    s->phi = phi;
    ok = (uint8_t *)realloc(s->ok, cap);
    if (ok == NULL) {
        return -1;
    }
    s->ok = ok;
    s->cap = cap;
    return 0;
}

/* One replayed sample: the application's calibrated measurements and the logged command. */
static void on_sample(const rawlog_record_t *rec, const app_output_t *out, void *user)
{
    samples_t *s = (samples_t *)user;
    const uint32_t lost = APP_DEGRADED_CURRENT | APP_DEGRADED_ANGLE;
    const int contiguous = s->have_last && rec->t_us - s->last_t_us == (uint64_t)APP_PERIOD_US;
    if (s->oom) {
        return;
    }
    if (s->n == s->cap && samples_grow(s) != 0) {
        s->oom = 1;
        return;
    }
    s->u[s->n] = rec->bridge_enable != 0u ? (double)rec->duty * (double)out->supply_V : 0.0;
    s->i[s->n] = (double)out->z[EKF_CH_CURRENT];
    s->phi[s->n] = (double)out->z[EKF_CH_ANGLE];
    s->ok[s->n] = rec->bridge_enable != 0u && (out->degraded & lost) == 0u && contiguous ? 1u : 0u;
    ++s->n;
    s->last_t_us = rec->t_us;
    s->have_last = 1;
}

static void usage(FILE *f)
{
    fprintf(f,
            "usage: %s [options] LOG -o PARAMS\n"
            "\n"
            "Estimates the throttle model's parameters (firmware/estimator/tv_model.h) from one open-loop raw\n"
            "log (CSV or binary TVRAWLOG, host_sim/replay/LOG_FORMATS.md; '-': stdin), read and validated as\n"
            "replay reads it, and writes them as a parameter file (key = value) that replay --params,\n"
            "host_sim --params and the Linux controller's configuration accept. Prints every estimate with its\n"
            "standard deviation and the fit quality, and which parameters the log could not identify (those\n"
            "keep the reader's defaults: their lines are written as comments).\n"
            "Recommended log: the identification excitation APP_MODE_IDENT, 30 s\n"
            "(host_sim --scenario ident --raw-log FILE; README \"Identification\").\n"
            "\n"
            "  -o, --out PARAMS        the parameter file to write (required)\n"
            "  --format auto|csv|bin   input format (default auto)\n"
            "  --on-error stop|skip    stop at the first bad input (default), or skip it and go on\n"
            "  --gear N                gear ratio motor : plate that splits the identified n Ke = n Kt into\n"
            "                          the model's Ke, Kt (default 40, the model's; only the product is seen)\n"
            "  --winding-temp C        the winding's temperature during the log [degC], -40 .. 180: the\n"
            "                          resistance is written referred to 20 degC, the model's reference\n"
            "                          (copper, +0.393 %%/K; default: the log's resistance as it is)\n"
            "  --quiet                 no progress lines (results and errors are still printed)\n"
            "  --help                  this text\n"
            "\n"
            "Exit codes: as replay (0 ok; 1 I/O error; 2 usage; 4 configuration rejected; 5..18 the input error\n"
            "that stopped the run; 19 finished after skipping input with --on-error skip), and\n"
            "20: too little excitation: the plate did not move enough both ways for the plate's parameters\n"
            "(nothing is written).\n",
            s_prog);
}

/* One key of the parameter file: written when identified, else a comment saying why. */
static void print_result(FILE *f, const id_result_t *r)
{
    int p;
    fprintf(f, "%-16s %14s %12s %9s  %s\n", "parameter", "estimate", "sigma", "sigma/%", "");
    for (p = 0; p < (int)ID_P_COUNT; ++p) {
        const double rel = 100.0 * r->sigma[p] / fabs(r->value[p]);
        fprintf(f, "%-16s %14.6g %12.3g %9.2f  [%s] %s%s\n", id_param_name((id_param_t)p), r->value[p], r->sigma[p],
                rel, id_param_unit((id_param_t)p), r->identified[p] ? "identified" : "NOT IDENTIFIED: ",
                r->identified[p] ? (p == (int)ID_P_MS && r->ms_is_mc ? " (no Stribeck drop seen: Ms = Mc)" : "") : r->why[p]);
    }
    fprintf(f, "fit quality: armature R^2 %.6f, RMS residual %.4g A (%lu samples); plate R^2 %.4f, RMS residual %.4g N m "
               "(%lu samples of free motion); stops RMS residual %.3g rad (%lu + %lu rest blocks); impacts RMS angle "
               "error %.3g rad (%lu impacts)\n",
            r->r2_elec, r->rms_elec_A, (unsigned long)r->n_elec, r->r2_mech, r->rms_mech_Nm, (unsigned long)r->n_mech,
            r->rms_stop_rad, (unsigned long)r->n_blocks[0], (unsigned long)r->n_blocks[1], r->rms_impact_rad,
            (unsigned long)r->n_impacts);
}

static double now_s(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    replay_options_t opt;
    replay_stats_t st;
    rlr_format_t format = RLR_FMT_AUTO;
    const char *in_path = NULL;
    const char *out_path = NULL;
    double gear = 40.0;
    int quiet = 0;
    int k;
    int rc;
    FILE *in;
    samples_t smp;
    id_result_t res;
    id_data_t d;
    const double t0 = now_s();
    static const char *const takes_value[] = {"-o", "--out", "--format", "--on-error", "--gear", "--winding-temp", NULL};
    double log_temp_C = (double)NAN;

    replay_options_default(&opt);
    memset(&smp, 0, sizeof smp);
    for (k = 1; k < argc; ++k) {
        const char *a = argv[k];
        const char *v = k + 1 < argc ? argv[k + 1] : NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return RLR_EXIT_OK;
        }
        if (strcmp(a, "--quiet") == 0) {
            quiet = 1;
            continue;
        }
        if (strcmp(a, "-") == 0 || a[0] != '-') {
            if (cli_set_input(s_prog, &in_path, a) != 0) {
                return CLI_EXIT_USAGE;
            }
            continue;
        }
        if (cli_option_value(s_prog, a, v, takes_value) != 0 || v == NULL) { /* (v: for the analyser) */
            return CLI_EXIT_USAGE;
        }
        ++k;
        if (strcmp(a, "--format") == 0) {
            if (rlr_format_from_name(v, &format) != TV_OK) {
                return usage_error("option %s: '%s' is not auto, csv or bin", a, v);
            }
        } else if (strcmp(a, "-o") == 0 || strcmp(a, "--out") == 0) {
            if (*v == '\0') {
                return usage_error("option %s: empty path", a);
            }
            out_path = v;
        } else if (strcmp(a, "--on-error") == 0) {
            if (cli_on_error(s_prog, a, v, &opt.skip_errors) != 0) {
                return CLI_EXIT_USAGE;
            }
        } else if (strcmp(a, "--winding-temp") == 0) {
            if (cli_parse_temp(v, &log_temp_C) != 0) {
                return usage_error("option %s: '%s' is not a temperature in -40 .. 180 degC", a, v);
            }
        } else {
            if (cli_parse_double(v, &gear) != 0 || !(gear > 0.0) || gear > 1000.0) {
                return usage_error("option %s: '%s' is not a number in (0, 1000]", a, v);
            }
        }
    }
    if (out_path == NULL) {
        return usage_error("no output: -o PARAMS is required");
    }
    if (cli_refuse_output_is_input(s_prog, in_path, out_path)) {
        return RLR_EXIT_USAGE;
    }
    in = cli_open_input(s_prog, &in_path);
    if (in == NULL) {
        return RLR_EXIT_IO;
    }

    /* Read and validate the log as replay does; its application calibrates every sample. */
    params_init(&s_params, "command line");
    opt.params = &s_params;
    opt.out = NULL;
    opt.diag = stderr;
    opt.on_sample = on_sample;
    opt.user = &smp;
    if (!quiet) {
        fprintf(stderr, "%s: reading %s ...\n", s_prog, in_path);
    }
    rc = rlr_open_file(&s_reader, in, in_path, format, 0u);
    if (rc != TV_OK) {
        fprintf(stderr, "%s: %s\n", s_prog, rlr_message(&s_reader));
        rc = rlr_exit_code(rlr_error(&s_reader));
    } else {
        (void)replay_run(&s_reader, &opt, &st);
        rc = replay_exit_code(&st);
        if (rc != RLR_EXIT_OK && rc != RLR_EXIT_SKIPPED) {
            replay_print_summary(stderr, &s_reader, &st, &opt);
        }
    }
    if (in != stdin) {
        (void)fclose(in);
    }
    if (rc != RLR_EXIT_OK && rc != RLR_EXIT_SKIPPED) {
        samples_free(&smp);
        return rc;
    }
    if (smp.oom) {
        fprintf(stderr, "%s: out of memory after %lu samples\n", s_prog, (unsigned long)smp.n);
        samples_free(&smp);
        return RLR_EXIT_IO;
    }

    d.n = smp.n;
    d.u_V = smp.u;
    d.i_A = smp.i;
    d.phi_rad = smp.phi;
    d.ok = smp.ok;
    d.Ts_s = (double)APP_PERIOD_US * 1e-6;
    {
        const int irc = id_run(&d, quiet ? NULL : stderr, &res);
        samples_free(&smp);
        if (irc == TV_ERR_RANGE) {
            fprintf(stderr, "%s: %s: %lu samples: too short to identify anything\n", s_prog, in_path, (unsigned long)d.n);
            return ID_EXIT_EXCITATION;
        }
        if (irc != TV_OK) {
            fprintf(stderr, "%s: identification failed: %s\n", s_prog, tv_status_str(irc));
            return RLR_EXIT_IO;
        }
    }
    if (!isnan(log_temp_C)) {
        (void)id_refer_resistance(&res, log_temp_C); /* validated above, once */
    }
    print_result(stdout, &res);
    if (!res.moved) {
        fprintf(stderr, "%s: %s: too little excitation: the plate did not move enough both ways in free motion to identify "
                        "its parameters (its angle spans %.4f .. %.4f rad; %s); nothing written. Record an open-loop log "
                        "that moves the plate both ways at several speeds and touches both stops (host_sim --scenario "
                        "ident, APP_MODE_IDENT).\n",
                s_prog, in_path, res.travel_lo_rad, res.travel_hi_rad, res.why[ID_P_J]);
        return ID_EXIT_EXCITATION;
    }
    {
        FILE *f = fopen(out_path, "w");
        char err[PARAMS_MSG_MAX];
        app_config_t cfg;
        if (f == NULL) {
            fprintf(stderr, "%s: cannot write %s: %s\n", s_prog, out_path, strerror(errno));
            return RLR_EXIT_IO;
        }
        rc = id_write_params(f, in_path, &res, gear);
        if (fclose(f) != 0 || rc != TV_OK) {
            fprintf(stderr, "%s: error writing %s\n", s_prog, out_path);
            return RLR_EXIT_IO;
        }
        /* what replay and host_sim will do with it: read it back and apply it */
        params_init(&s_params, out_path);
        app_config_default(&cfg);
        if (params_load(&s_params, out_path, err, sizeof err) != TV_OK || params_apply(&s_params, &cfg, err, sizeof err) != TV_OK) {
            fprintf(stderr, "%s: the written file is not accepted: %s\n", s_prog, err);
            return RLR_EXIT_IO;
        }
    }
    fprintf(stderr, "%s: wrote %s (%.2f s)\n", s_prog, out_path, now_s() - t0);
    return rc;
}
